"""The Intrinsic domain (issue 11) from Blender: Suzanne with a Subdivision modifier
(Blender's own UVs: many islands and seams), the continuous model on an intrinsic
Delaunay triangulation of the surface, live and baked. The texture it writes shows no
seam lines: the pheromone within 2 texels of an island's border is, on average, what it
is farther in. The panel shows the triangulation; the settings are saved (the
persistence test covers the two properties)."""

import math
import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h
from test_ui import draw_all, labels


def intrinsic_suzanne(resolution="256", agents=60000, seed=h.SEED):
    """Suzanne, Subdivision level 1, the continuous model with turnover (a network that
    renews itself within a second, so snapshots 0.5 s apart are nearly independent) at
    half the default pattern scale (many trails, so a mean over a band of texels is
    steady), on the Intrinsic domain."""
    obj = h.add_primitive("monkey")
    modifier = obj.modifiers.new("Subdivision", 'SUBSURF')
    modifier.levels = 1
    h.configure(obj, resolution=resolution, agents=agents, seed=seed)
    obj.moldtex.model = 'CONTINUOUS'
    obj.moldtex.pattern_scale = 0.5
    obj.moldtex.continuous.mean_lifetime = 0.5
    obj.moldtex.continuous.activation_time = 0.2
    obj.moldtex.domain = 'INTRINSIC'
    return obj


class IntrinsicDomainTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_intrinsic_")

    def tearDown(self):
        h.clear_scene()
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_live_on_suzanne_has_no_seam_lines(self):
        engine = h.engine()
        obj = intrinsic_suzanne(seed=1)
        entry = h.run(obj, 60)
        self.assertEqual(entry.sim.get_config()["domain"], engine.DOMAIN_INTRINSIC)
        self.assertIn("intrinsic", entry.backend_name)
        info = entry.domain_info
        classes = entry.sim.read_texel_classes()
        island = sum(1 for c in classes if c == 1)
        # About one vertex per island texel (Chew's bound: 0.4 - 1.6 per bound²).
        self.assertGreater(info["cell_count"], 0.3 * island, info)
        self.assertLess(info["cell_count"], 2.0 * island, info)
        print(f"    Suzanne: {info['cell_count']:,} vertices for {island:,} island texels, "
              f"built in {info['build_seconds']:.2f} s")
        # The panel says so.
        text = labels(draw_all(self, obj))
        self.assertIn(f"Intrinsic: {info['cell_count']:,} vertices", text)
        # No seam lines: texels within 2 of an island border hold what the others hold,
        # within 10% (the bound), over 4 seeds x 6 snapshots 0.5 s apart from
        # 1 s on. One seed's ratio spreads about 5% (seeds 1-6 measured 0.89, 0.97, 0.98,
        # 1.02, 0.92, 1.03 on Blender 3.4): on Suzanne the seams also follow its rims and
        # eye sockets, so part of that is geometry. (The texture domain's ratio at seed 1
        # was 1.01 here; the core test IntrinsicSimulation.NoTraceOfTheUvSeams, on a flat
        # cut plane, is where the two domains part: 1.82 against 1.03.)
        border, inner = self.seam_sums(obj)
        for seed in (2, 3, 4):
            obj.moldtex.seed = seed
            h.run(obj, 60)
            b, i = self.seam_sums(obj)
            border += b
            inner += i
        ratio = border / inner
        print(f"    intrinsic domain, seeds 1-4: ratio {ratio:.3f}")
        self.assertGreater(ratio, 0.9)
        self.assertLess(ratio, 1.1)

    def seam_sums(self, obj):
        """Sums over 6 snapshots of the mean u / U near island borders and elsewhere."""
        entry = h.live().get(obj.name)
        classes = entry.sim.read_texel_classes()
        width = int(obj.moldtex.resolution)
        near = h.near_island_border(classes, width, 2)
        border = inner = 0.0
        for _ in range(6):
            self.assertEqual(bpy.ops.moldtex.step(steps=30), {'FINISHED'})
            pixels = h.image_pixels(obj)
            values = {i: pixels[4 * i] for i in near}
            self.assertTrue(all(math.isfinite(v) and v >= 0.0 for v in values.values()))
            b = [v for i, v in values.items() if near[i]]
            n = [v for i, v in values.items() if not near[i]]
            border += sum(b) / len(b)
            inner += sum(n) / len(n)
        self.assertGreater(max(values.values()), 1.5, "trails stand above U")
        print(f"    {obj.moldtex.domain.lower()} domain, seed {obj.moldtex.seed}: near seams "
              f"{border / 6:.3f} U, elsewhere {inner / 6:.3f} U, ratio {border / inner:.3f}")
        return border, inner

    def test_bake_writes_what_a_fresh_simulation_holds(self):
        obj = intrinsic_suzanne(resolution="128", agents=8000)
        h.bake_settings(obj, self.folder, 1, 2, 20, "EXR_HALF")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        sim = h.fresh_sim(obj)
        try:
            self.assertEqual(sim.domain_info()["domain"], h.engine().DOMAIN_INTRINSIC)
            for frame in (1, 2):
                sim.step(20)
                expected = sim.read_rgba()[0::4]
                path = os.path.join(self.folder, f"{obj.name}_{frame:04d}.exr")
                pixels, size = h.load_pixels(path)
                self.assertEqual(size, (128, 128))
                values = pixels[0::4]
                worst = max(abs(a - b) / max(1.0, b) for a, b in zip(values, expected))
                self.assertLessEqual(worst, 1.0 / 2048, f"frame {frame}")
        finally:
            sim.release()

    def test_momas_keeps_the_texture_gray_scott_runs_intrinsic(self):
        engine = h.engine()
        obj = intrinsic_suzanne(resolution="128", agents=500)
        obj.moldtex.model = 'MOMAS'  # works in texels: the setting does not apply
        entry = h.run(obj, 1)
        self.assertEqual(entry.sim.get_config()["domain"], engine.DOMAIN_TEXTURE)
        obj.moldtex.model = 'GRAY_SCOTT'  # runs on the intrinsic domain too
        entry = h.run(obj, 2)
        self.assertEqual(entry.sim.get_config()["domain"], engine.DOMAIN_INTRINSIC)
        self.assertGreater(entry.stats["coverage"], 0.0)

    def test_triangulation_builds_ahead_with_progress_and_cancel(self):
        """What Start and Reset do in the interface before they create the simulation:
        the triangulation builds on the core's thread; the panel shows its progress;
        cancelling it keeps nothing; a finished build is what Reset then uses."""
        import time

        from moldtex.sim import session as live
        engine = h.engine()
        obj = intrinsic_suzanne(resolution="1024", seed=3)  # ~300 k vertices: seconds
        depsgraph = bpy.context.evaluated_depsgraph_get()
        build = live.start_domain_build(obj, depsgraph, rebuild=True)
        self.assertIsNotNone(build)
        try:
            while True:
                progress = build.progress()
                if (progress["state"] != engine.BAKE_RUNNING
                        or (progress["stage"] == engine.BUILD_REFINING
                            and progress["vertex_count"] > 0)):
                    break
                time.sleep(0.005)
            self.assertEqual(progress["state"], engine.BAKE_RUNNING,
                             "the build ended before it could be looked at")
            text = labels(draw_all(self, obj))
            self.assertIn("Building the intrinsic triangulation:", text)
            self.assertTrue(live.cancel_domain_build(obj))
            with self.assertRaises(engine.EngineError) as raised:
                build.wait()
            self.assertEqual(raised.exception.status, engine.ERROR_CANCELLED)
            progress = build.progress()
            self.assertEqual(progress["state"], engine.BAKE_CANCELLED)
            self.assertLess(progress["fraction"], 1.0)
        finally:
            live.end_domain_build(obj.name)
        self.assertIsNone(live.domain_build_status(obj))

        # A texture domain simulation needs no build.
        obj.moldtex.resolution = "128"
        obj.moldtex.domain = 'TEXTURE'
        self.assertIsNone(live.start_domain_build(obj, depsgraph, rebuild=True))
        obj.moldtex.domain = 'INTRINSIC'
        build = live.start_domain_build(obj, depsgraph, rebuild=True)
        try:
            build.wait()
            progress = build.progress()
        finally:
            live.end_domain_build(obj.name)
        self.assertEqual(progress["state"], engine.BAKE_FINISHED)
        self.assertEqual(progress["fraction"], 1.0)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        info = live.get(obj.name).domain_info
        self.assertTrue(info["from_cache"], info)
        self.assertEqual(info["cell_count"], progress["vertex_count"])

    def test_agents_live_on_faces_whose_uvs_have_zero_area(self):
        """A careless unwrap (here: two columns of a 16 × 16 plane pinned to one UV
        line) leaves faces with no UV area. The Intrinsic domain walks the surface in 3D,
        so its agents live there in proportion to the area (2 of 16 columns: 0.125 of
        the plane); the Texture domain cannot measure texels there and keeps them out
        (they are walls to it, as the README says). Random spawn and turnover: agents
        are born and walk there."""
        obj = h.subdivided_plane()
        mesh = obj.data
        uvs = mesh.uv_layers.active.data
        for loop in mesh.loops:
            if abs(mesh.vertices[loop.vertex_index].co.x) < 0.13:  # x = -0.125, 0, 0.125
                uvs[loop.index].uv = (0.5, uvs[loop.index].uv[1])
        mesh.update()
        h.configure(obj, resolution="128", agents=4000, seed=2)
        obj.moldtex.model = 'CONTINUOUS'
        obj.moldtex.continuous.mean_lifetime = 0.5
        obj.moldtex.continuous.activation_time = 0.2
        shares = {}
        for domain in ('INTRINSIC', 'TEXTURE'):
            obj.moldtex.domain = domain
            h.run(obj, 60)
            positions = h.agent_positions(obj)
            shares[domain] = sum(1 for p in positions if abs(p[0]) < 0.125) / len(positions)
            print(f"    {domain.lower()} domain: {shares[domain]:.3f} of the agents on the "
                  f"collapsed strip (its area: 0.125)")
        # Binomial noise of 4,000 agents at 0.125: 0.005; the pattern gathers and
        # empties regions by more, so a wide band around the area share.
        self.assertGreater(shares['INTRINSIC'], 0.07)
        self.assertLess(shares['INTRINSIC'], 0.2)
        self.assertEqual(shares['TEXTURE'], 0.0)


if __name__ == "__main__":
    unittest.main()
