"""Surface map tools (issue 12, Layton et al. §6, Fig. 14-17): the four operators on
Suzanne write vertex groups and attributes with sane values, the gradient drives the
continuous model's bias live and in a bake, bad inputs are messages, and everything
survives saving and reloading the .blend."""

import math
import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h


def call(operator, **kwargs):
    """(result, message): the operator's result, or the error it reported (Blender
    raises RuntimeError for those when called from Python)."""
    try:
        return operator(**kwargs), ""
    except RuntimeError as error:
        return {'CANCELLED'}, str(error)


def group_weights(obj, name):
    """Weight of every vertex in group `name` (None where unassigned)."""
    index = obj.vertex_groups[name].index
    weights = [None] * len(obj.data.vertices)
    for vertex in obj.data.vertices:
        for element in vertex.groups:
            if element.group == index:
                weights[vertex.index] = element.weight
    return weights


def set_group(obj, name, predicate):
    """Vertex group `name` with weight 1 on the vertices whose position passes."""
    group = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
    chosen = [v.index for v in obj.data.vertices if predicate(v.co)]
    group.add(chosen, 1.0, 'REPLACE')
    return chosen


def attribute_values(obj, name, key="value", width=1):
    attribute = obj.data.attributes[name]
    values = [0.0] * (width * len(attribute.data))
    attribute.data.foreach_get(key, values)
    return attribute, values


def components(mesh):
    """Connected component id of every vertex (over edges)."""
    parent = list(range(len(mesh.vertices)))

    def find(v):
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v
    for edge in mesh.edges:
        a, b = find(edge.vertices[0]), find(edge.vertices[1])
        parent[a] = b
    return [find(v) for v in range(len(mesh.vertices))]


def suzanne():
    obj = h.add_primitive("monkey")
    # The source: the vertex at the tip of the nose region (largest -y on the head).
    head = components(obj.data)
    biggest = max(set(head), key=head.count)
    tip = min((v for v in obj.data.vertices if head[v.index] == biggest), key=lambda v: v.co.y)
    group = obj.vertex_groups.new(name="source")
    group.add([tip.index], 1.0, 'REPLACE')
    return obj, tip.index, head, biggest


class MapToolTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_map_tools_")

    def tearDown(self):
        h.clear_scene()
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_geodesic_distance_on_suzanne(self):
        obj, tip, head, biggest = suzanne()
        obj.moldtex_map_tools.distance_source = "source"
        self.assertEqual(bpy.ops.moldtex.map_distance(), {'FINISHED'})
        weights = group_weights(obj, "Moldtex Distance")
        self.assertTrue(all(w is not None and 0.0 <= w <= 1.0 for w in weights))
        self.assertEqual(weights[tip], 0.0)
        attribute, distance = attribute_values(obj, "moldtex_distance")
        self.assertEqual((attribute.domain, attribute.data_type), ('POINT', 'FLOAT'))
        self.assertEqual(distance[tip], 0.0)
        source = obj.data.vertices[tip].co
        on_head = [v.index for v in obj.data.vertices if head[v.index] == biggest]
        far = max(distance[v] for v in on_head)
        # Suzanne's eyes are separate pieces: no path over the surface reaches them,
        # so they measure -1 (and weigh 1, "far").
        others = [v for v in range(len(distance)) if head[v] != biggest]
        self.assertTrue(others)
        self.assertTrue(all(distance[v] == -1.0 and weights[v] == 1.0 for v in others))
        # On the head: a path over the surface is never shorter than the straight
        # line. The heat method on Suzanne (~500 vertices, skinny and obtuse triangles
        # at the lips and eyes, no intrinsic Delaunay remeshing) comes short of it at a
        # few vertices: measured 94 % of those farther than 0.2 at >= 0.95 x the
        # straight line, the worst at 0.79 x. Asked: 90 % at 0.95 x, all at 0.7 x.
        ratios = []
        for v in on_head:
            straight = (obj.data.vertices[v].co - source).length
            if straight > 0.2:
                ratios.append(distance[v] / straight)
            self.assertAlmostEqual(weights[v], distance[v] / far, places=5)
        print(f"\ndistance / straight line on Suzanne: worst {min(ratios):.3f}, "
              f"{sum(r >= 0.95 for r in ratios) / len(ratios):.1%} at >= 0.95")
        self.assertGreaterEqual(sum(r >= 0.95 for r in ratios), 0.9 * len(ratios))
        self.assertGreaterEqual(min(ratios), 0.7)
        by_straight = sorted(on_head, key=lambda v: (obj.data.vertices[v].co - source).length)
        near, away = by_straight[:20], by_straight[-20:]
        self.assertLess(max(distance[v] for v in near), min(distance[v] for v in away))
        self.assertGreater(len({round(w, 3) for w in weights}), 50)  # not constant

    def test_laplace_blend_between_two_groups(self):
        obj, _, head, biggest = suzanne()
        low = set_group(obj, "left", lambda co: co.x < -0.6)
        high = set_group(obj, "right", lambda co: co.x > 0.6)
        tools = obj.moldtex_map_tools
        tools.blend_low, tools.blend_high = "left", "right"
        self.assertEqual(bpy.ops.moldtex.map_blend(), {'FINISHED'})
        weights = group_weights(obj, "Moldtex Blend")
        self.assertTrue(all(w is not None and 0.0 <= w <= 1.0 for w in weights))
        self.assertTrue(all(weights[v] == 0.0 for v in low))
        self.assertTrue(all(abs(weights[v] - 1.0) < 1e-6 for v in high))
        middle = [v.index for v in obj.data.vertices
                  if abs(v.co.x) < 0.1 and head[v.index] == biggest]
        self.assertTrue(middle)
        # Symmetric regions on a symmetric head: the middle is near one half.
        mean = sum(weights[v] for v in middle) / len(middle)
        self.assertAlmostEqual(mean, 0.5, delta=0.1)
        # Increasing from left to right (harmonic: no bumps).
        xs = sorted((obj.data.vertices[v].co.x, weights[v]) for v in range(len(weights))
                    if head[v] == biggest)
        left = [w for x, w in xs if -0.5 < x < -0.3]
        right = [w for x, w in xs if 0.3 < x < 0.5]
        self.assertLess(max(left), min(right))

    def test_blur_smooths_a_group(self):
        obj, _, _, _ = suzanne()
        top = set(set_group(obj, "top", lambda co: co.z > 0.0))
        tools = obj.moldtex_map_tools
        tools.blur_source, tools.blur_radius = "top", 0.15
        self.assertEqual(bpy.ops.moldtex.map_blur(), {'FINISHED'})
        weights = group_weights(obj, "Moldtex Blur")
        self.assertTrue(all(w is not None and 0.0 <= w <= 1.0 for w in weights))
        self.assertGreater(sum(1 for w in weights if 0.05 < w < 0.95), 20)  # a soft edge
        # Edges jump less: the summed squared difference along edges (a Dirichlet
        # energy) drops: the 0/1 step spreads over a few edges (radius 0.15, Suzanne's
        # edges ~0.1), so the squares of the now smaller jumps fall (measured 62 ->
        # 24); asked: at least 2-fold.
        before = sum(((a in top) - (b in top)) ** 2 for a, b in
                     (e.vertices for e in obj.data.edges))
        after = sum((weights[a] - weights[b]) ** 2 for a, b in (e.vertices for e in obj.data.edges))
        print(f"\nblur: edge energy {before:.1f} -> {after:.2f}")
        self.assertLess(after, before / 2)
        # Deep inside each region the value stays: top 1, bottom 0 (radius 0.15).
        self.assertGreater(min(weights[v.index] for v in obj.data.vertices if v.co.z > 0.6), 0.9)
        self.assertLess(max(weights[v.index] for v in obj.data.vertices if v.co.z < -0.6), 0.1)

    def _gradient_bias(self, obj):
        tools = obj.moldtex_map_tools
        tools.distance_source = "source"
        self.assertEqual(bpy.ops.moldtex.map_distance(), {'FINISHED'})
        tools.gradient_source = "Moldtex Distance"
        self.assertEqual(bpy.ops.moldtex.map_gradient_bias(), {'FINISHED'})
        attribute, vectors = attribute_values(obj, "moldtex_bias", "vector", 3)
        self.assertEqual((attribute.domain, attribute.data_type), ('FACE', 'FLOAT_VECTOR'))
        self.assertEqual(len(vectors), 3 * len(obj.data.polygons))
        return vectors

    def test_gradient_to_bias_drives_the_continuous_model(self):
        obj, _, _, _ = suzanne()
        vectors = self._gradient_bias(obj)
        lengths = [math.sqrt(sum(c * c for c in vectors[3 * f:3 * f + 3]))
                   for f in range(len(obj.data.polygons))]
        # Normalized: unit vectors, 0 only where the map is flat: the eyes (64 of 500
        # faces), unreachable, weigh 1 everywhere.
        self.assertGreater(sum(1 for n in lengths if abs(n - 1.0) < 1e-4), 0.8 * len(lengths))
        self.assertTrue(all(n < 1e-6 or abs(n - 1.0) < 1e-4 for n in lengths))
        # Along the surface: each triangle's gradient lies in its plane, so a face's
        # (the mean of its triangles') is nearly normal to the face normal; Suzanne's
        # quads are not planar, hence a bound on the mean |cos| of 0.1.
        cosines = [abs(sum(a * b for a, b in zip(vectors[3 * f.index:3 * f.index + 3], f.normal)))
                   for f in obj.data.polygons]
        self.assertLess(sum(cosines) / len(cosines), 0.1)
        # The continuous model with the bias from the attribute (and without).
        h.configure(obj, resolution="128", agents=4000)
        settings = obj.moldtex
        settings.model = 'CONTINUOUS'
        settings.pattern_scale = 1.0
        cont = settings.continuous
        cont.bias_source = 'ATTRIBUTE'
        self.assertEqual(cont.bias_attribute, "moldtex_bias")
        cont.bias_strength, cont.bias_symmetry = 6.0, 1
        entry = h.run(obj, 60)
        self.assertEqual(entry.bias_key[0][0], "ATTRIBUTE")
        biased = list(h.image_pixels(obj)[0::4])
        self.assertTrue(all(math.isfinite(v) for v in biased))
        cont.bias_strength = 0.0
        h.run(obj, 60)
        plain = list(h.image_pixels(obj)[0::4])
        changed = sum(1 for a, b in zip(biased, plain) if abs(a - b) > 1e-3)
        self.assertGreater(changed, len(plain) // 10, "the bias does not change the pattern")
        # The bake gets the same bias: its last frame is the live pattern after as many
        # steps (half floats: 11 significant bits).
        cont.bias_strength = 6.0
        h.run(obj, 60)
        live_pixels = list(h.image_pixels(obj)[0::4])
        h.bake_settings(obj, self.folder, 1, 2, 30, "EXR_HALF")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        files = sorted(f for f in os.listdir(self.folder) if f.endswith(".exr"))
        self.assertEqual(len(files), 2, files)
        pixels, size = h.load_pixels(os.path.join(self.folder, files[-1]))
        self.assertEqual(size, (128, 128))
        baked = pixels[0::4]
        worst = max(abs(a - b) / max(1.0, abs(b)) for a, b in zip(baked, live_pixels))
        self.assertLessEqual(worst, 1.0 / 1024)
        # A missing attribute is a message, not a traceback.
        cont.bias_attribute = "no_such_attribute"
        result, message = call(bpy.ops.moldtex.reset)
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("no_such_attribute", message)

    def test_bad_inputs_are_messages(self):
        obj, _, _, _ = suzanne()
        tools = obj.moldtex_map_tools
        tools.distance_source = "missing"
        result, message = call(bpy.ops.moldtex.map_distance)
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("no vertex group 'missing'", message)
        obj.vertex_groups.new(name="empty")
        tools.distance_source = "empty"
        result, message = call(bpy.ops.moldtex.map_distance)
        self.assertIn("no vertex of 'empty'", message)
        tools.blend_low, tools.blend_high = "source", "source"
        result, message = call(bpy.ops.moldtex.map_blend)
        self.assertIn("in both", message)
        tools.gradient_source = "nothing"
        result, message = call(bpy.ops.moldtex.map_gradient_bias)
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("nothing", message)
        set_group(obj, "all", lambda co: True)
        tools.gradient_source = "all"
        result, message = call(bpy.ops.moldtex.map_gradient_bias)
        self.assertIn("constant", message)
        # Not a mesh: the operators do not run.
        bpy.ops.object.empty_add()
        self.assertFalse(bpy.ops.moldtex.map_distance.poll())
        # Edit Mode: the tool leaves it, writes, and comes back.
        h.activate(obj)
        tools.distance_source = "source"
        bpy.ops.object.mode_set(mode='EDIT')
        self.assertEqual(bpy.ops.moldtex.map_distance(), {'FINISHED'})
        self.assertEqual(obj.mode, 'EDIT')
        bpy.ops.object.mode_set(mode='OBJECT')

    def test_results_and_settings_survive_save_and_reload(self):
        obj, tip, _, _ = suzanne()
        name = obj.name
        vectors = self._gradient_bias(obj)
        tools = obj.moldtex_map_tools
        tools.blur_radius, tools.time_factor = 0.25, 2.0
        obj.moldtex.continuous.bias_source = 'ATTRIBUTE'
        weights = group_weights(obj, "Moldtex Distance")
        path = os.path.join(self.folder, "maps.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        obj = bpy.data.objects[name]
        self.assertEqual(group_weights(obj, "Moldtex Distance"), weights)
        self.assertEqual(attribute_values(obj, "moldtex_bias", "vector", 3)[1], vectors)
        self.assertEqual(attribute_values(obj, "moldtex_distance")[1][tip], 0.0)
        tools = obj.moldtex_map_tools
        self.assertAlmostEqual(tools.blur_radius, 0.25, places=6)
        self.assertAlmostEqual(tools.time_factor, 2.0, places=6)
        self.assertEqual(tools.distance_source, "source")
        self.assertEqual(obj.moldtex.continuous.bias_source, 'ATTRIBUTE')
        self.assertEqual(obj.moldtex.continuous.bias_attribute, "moldtex_bias")
        # And the tools run again on the reloaded file.
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.map_distance(), {'FINISHED'})


if __name__ == "__main__":
    unittest.main()
