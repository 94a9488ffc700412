# SPDX-License-Identifier: GPL-3.0-or-later
"""Surface brushes (plasmodial-slime-readme.md "Brushes"): paint and erase obstacles,
attractors and spawn regions (the Fields image), slime (agents of the live simulation)
and food (Empties of the Food collection) on the 3D surface.

A dab lands where a ray meets the surface (the core's Embree ray cast gives triangle
and barycentrics); its radius is measured on the surface (the core walks geodesics from
the centre). Every stroke, from the viewport tool or from moldtex.brush_stroke, is one
step of a per-object history that Undo/Redo Stroke walk back and forth:
  fields  the image's pixels before and after (zlib-compressed: strokes touch little),
  slime   the core tags the stroke's agents with a batch number and keeps the agents it
          erased, so undo takes them out / puts them back (redo repeats the dabs, which
          places the same agents again),
  food    the Empties it created or removed.
Blender's own undo does not reach the image's pixels or the core, hence this history.

This module talks to the core only through the binding (engine/) and to the live simulations
only through sim/session.py.
"""

import array
import time
import weakref
import zlib

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty)
from mathutils import Matrix, Vector

from .. import engine
from ..data import image_io
from ..settings.enums import repair_enums
from ..sim import convert
from ..sim import session as live
from ..data.mesh_export import (MeshExportError, export_object, export_scale,
                          length_in_mesh_units, world_to_mesh)

TARGETS = (
    ('OBSTACLE', "Obstacle", "Walls no agent enters (green channel of the Fields image)",
     'MOD_MASK', 0),
    ('ATTRACTOR', "Attractor", "Regions that pull agents harder than any trail (blue "
     "channel of the Fields image)", 'FORCE_MAGNETIC', 1),
    ('SPAWN', "Spawn", "Where agents start with Start = Spawn Map (red channel of the "
     "Fields image; used at the next Reset)", 'OUTLINER_OB_POINTCLOUD', 2),
    ('SLIME', "Slime", "Adds agents to the live simulation (erase removes them); in a "
     "reaction-diffusion model, which has no agents, seeds its pattern (erase clears it)",
     'OUTLINER_OB_FORCE_FIELD', 3),
    ('FOOD', "Food", "Places food Empties in the Food collection (erase removes them)",
     'FORCE_FORCE', 4),
)
FIELD_CHANNELS = {'SPAWN': 0, 'OBSTACLE': 1, 'ATTRACTOR': 2}
MAX_HISTORY = 64          # strokes kept per object for undo
DAB_SPACING = 0.35        # distance between dabs of a stroke, in brush radii
_PUSH_INTERVAL = 0.1      # seconds between image uploads / core updates during a stroke


class BrushError(Exception):
    """A problem the user can act on (no hit, wrong Fields source, ...)."""


class MoldtexBrushSettings(bpy.types.PropertyGroup):
    target: EnumProperty(name="Paint", items=TARGETS, default='OBSTACLE',
                         description="What the brush paints")
    erase: BoolProperty(name="Erase", default=False,
                        description="Remove instead of add (E toggles it while painting)")
    radius: FloatProperty(
        name="Radius", default=0.1, min=1e-5, max=1e4, soft_min=0.001, soft_max=10.0,
        subtype='DISTANCE', unit='LENGTH',
        description="Brush radius, measured along the surface ([ and ] change it while "
                    "painting)")
    strength: FloatProperty(
        name="Strength", default=1.0, min=0.0, max=1.0, subtype='FACTOR',
        description="How far one dab moves the painted values towards full (or, erasing, "
                    "towards zero); erasing slime, the chance that an agent under the "
                    "brush centre is removed (times the falloff towards the rim)")
    falloff: FloatProperty(
        name="Falloff", default=0.5, min=0.0, max=1.0, subtype='FACTOR',
        description="0 = hard edge; 1 = the effect fades smoothly from the centre to the "
                    "rim (fields and slime; food is placed or removed whole)")
    agents_per_dab: IntProperty(
        name="Agents per Dab", default=2000, min=1, max=1_000_000,
        description="Agents per Dab: agents a slime dab adds, spread evenly over the "
                    "brush disk")
    species: IntProperty(name="Species", default=1, min=1, max=4,
                         description="Species of the agents a slime dab adds")
    food_strength: FloatProperty(
        name="Food Strength", default=1.0, min=0.0, soft_max=100.0,
        description="Food Strength: moldtex_strength of new food Empties (scene units²)")
    food_amount: FloatProperty(
        name="Food Amount", default=-1.0, min=-1.0, soft_max=1e6,
        description="Food Amount: moldtex_amount of new food Empties, units of food "
                    "(-1 = never runs out)")


# ---- where the brush lands ---------------------------------------------------------

class _SurfaceCache:
    """The core surface of an object's exported mesh. Exporting costs time on big
    meshes, so the mesh is read again only after its geometry changed (sim/handlers.py
    calls invalidate), its UV map setting or its non-uniform scale changed; a new
    surface is built only when the exported data really differ."""

    def __init__(self):
        self.items = {}  # object name -> [signature, engine.Surface, key, valid]

    def get(self, obj, depsgraph, uv_map):
        data = obj.data
        key = (uv_map, tuple(export_scale(obj) or ()), obj.as_pointer(),
               data.as_pointer(), len(data.vertices), len(data.polygons))
        cached = self.items.get(obj.name)
        if cached is not None and cached[3] and cached[2] == key:
            return cached[1]
        mesh = export_object(obj, depsgraph, uv_map)
        if cached is not None and cached[0] == mesh.signature:
            cached[2], cached[3] = key, True
            return cached[1]
        if cached is not None:
            cached[1].release()
        surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs,
                                 mesh.triangle_uvs)
        self.items[obj.name] = [mesh.signature, surface, key, True]
        return surface

    def invalidate(self, name=None):
        for item_name, cached in self.items.items():
            if name is None or item_name == name:
                cached[3] = False

    def clear(self):
        for cached in self.items.values():
            cached[1].release()
        self.items.clear()


_surfaces = _SurfaceCache()


def _uv_map_setting(obj):
    entry = live.get(obj.name)
    if entry is not None and entry.sim is not None and not entry.baking:
        return entry.uv_map_setting
    return obj.moldtex.uv_map


def cast(obj, depsgraph, origin, direction):
    """Where a world-space ray meets obj's surface: dict with triangle, bary, position
    (mesh space), world (world space), normal (world space) and the surface; or None.
    direction (0, 0, 0) means: the surface point nearest `origin`."""
    surface = _surfaces.get(obj, depsgraph, _uv_map_setting(obj))
    to_mesh = world_to_mesh(obj)
    o = to_mesh @ Vector(origin)
    d = to_mesh.to_3x3() @ Vector(direction)
    if d.length == 0.0:
        triangle, bary, _distance = surface.closest_point(tuple(o))
        position, _uv = surface.evaluate(triangle, bary)
        hit = {"triangle": triangle, "bary": tuple(bary), "position": tuple(position),
               "normal": None}
    else:
        hit = surface.ray_cast(tuple(o), tuple(d))
        if hit is None:
            return None
    to_world = to_mesh.inverted()
    hit["world"] = tuple(to_world @ Vector(hit["position"]))
    normal = hit.get("normal")
    if normal is not None:
        n = (to_mesh.to_3x3().transposed() @ Vector(normal))
        hit["world_normal"] = tuple(n.normalized()) if n.length > 0 else (0.0, 0.0, 1.0)
    else:
        hit["world_normal"] = None
    hit["surface"] = surface
    return hit


def _brush_dict(obj, settings, hit, channel, erase):
    brush = engine.default_brush()
    brush.update(triangle=hit["triangle"], bary=tuple(hit["bary"]),
                 radius=length_in_mesh_units(obj, settings.radius),
                 strength=float(settings.strength), falloff=float(settings.falloff),
                 mode=engine.BRUSH_ERASE if erase else engine.BRUSH_PAINT,
                 channel=channel, value=1.0)
    return brush


# ---- the Fields image ----------------------------------------------------------------

def fields_image_name(obj):
    return f"Moldtex Fields {obj.name}"


def ensure_fields_image(obj):
    """The object's Fields image; a new black float image (Non-Color) at the
    simulation's resolution if there is none."""
    settings = obj.moldtex
    image = settings.fields_image
    if image is None:
        size = int(settings.resolution)
        image = bpy.data.images.new(fields_image_name(obj), size, size, alpha=True,
                                    float_buffer=True)
        image.colorspace_settings.name = 'Non-Color'
        image.generated_color = (0.0, 0.0, 0.0, 0.0)
        settings.fields_image = image
    return image


def read_image(image):
    width, height = image.size
    if width == 0 or height == 0:
        raise BrushError(f"The Fields image '{image.name}' has no pixels (is its file "
                         f"missing?): pick another image or clear Fields.")
    if image.channels != 4:
        raise BrushError(f"The Fields image '{image.name}' has {image.channels} channels; "
                         f"the brush paints RGBA images: clear Fields to let the brush "
                         f"make one.")
    return image_io.read_pixels(image)


def push_fields(obj, pixels, width, height, final=True):
    """Sends painted fields to the object's live simulation (if any). An image of
    another size than the simulation is resampled (slow), so only when final. Returns a
    message when the core refuses them (e.g. an empty spawn map), else ""."""
    entry = live.get(obj.name)
    if entry is None or entry.sim is None or entry.baking:
        return ""
    try:
        if (entry.sim.width, entry.sim.height) == (width, height):
            entry.sim.set_fields(pixels)
            live.note_fields_pushed(obj, pixels)
        elif final:
            live.push_fields(obj)  # resamples to the simulation's size
    except engine.EngineError as error:
        return str(error)
    return ""


# ---- strokes and their history ---------------------------------------------------------

class _History:
    def __init__(self):
        self.undo = []
        self.redo = []
        self.next_batch = 1

    def push(self, edit):
        self.undo.append(edit)
        del self.undo[:-MAX_HISTORY]
        self.redo.clear()


_histories = {}


def history(name):
    entry = _histories.get(name)
    if entry is None:
        entry = _histories[name] = _History()
    return entry


def forget(name=None):
    """Drops the history (and cached surface) of one object, or of all."""
    if name is None:
        _histories.clear()
        _surfaces.clear()
    else:
        _histories.pop(name, None)
        cached = _surfaces.items.pop(name, None)
        if cached is not None:
            cached[1].release()


def mesh_changed(name=None):
    """The mesh of one object (or of any) may have changed: read it again before the
    next dab."""
    _surfaces.invalidate(name)


def counts(name):
    entry = _histories.get(name)
    return (len(entry.undo), len(entry.redo)) if entry is not None else (0, 0)


class _FieldsEdit:
    label = "fields"

    def __init__(self, obj, image, channel):
        self.object_name = obj.name
        self.image_name = image.name
        self.size = tuple(image.size)
        self.pixels = read_image(image)
        self.before = zlib.compress(self.pixels.tobytes(), 1)
        self.after = None
        self.channel = channel
        self.changed = 0
        self._last_push = 0.0
        self.message = ""

    def dab(self, obj, settings, hit):
        brush = _brush_dict(obj, settings, hit, self.channel, settings.erase)
        width, height = self.size
        self.changed += hit["surface"].paint(width, height, self.pixels, brush)
        now = time.perf_counter()
        if now - self._last_push >= _PUSH_INTERVAL:
            self._show(obj, final=False)
            self._last_push = now

    def _show(self, obj, final):
        image = bpy.data.images.get(self.image_name)
        if image is None or tuple(image.size) != self.size:
            return
        image_io.upload(image, self.pixels)
        self.message = push_fields(obj, self.pixels, *self.size, final=final)

    def finish(self, obj):
        self._show(obj, final=True)
        self.after = zlib.compress(self.pixels.tobytes(), 1)
        self.pixels = None  # the image holds them now
        return self.changed > 0

    def _restore(self, data):
        image = bpy.data.images.get(self.image_name)
        obj = bpy.data.objects.get(self.object_name)
        if image is None or tuple(image.size) != self.size:
            raise BrushError(f"The Fields image '{self.image_name}' is gone or was "
                             f"resized since this stroke: it cannot be undone.")
        pixels = array.array("f")
        pixels.frombytes(zlib.decompress(data))
        image_io.upload(image, pixels)
        return push_fields(obj, pixels, *self.size) if obj is not None else ""

    def undo(self):
        return self._restore(self.before)

    def redo(self):
        return self._restore(self.after)


class _SlimeEdit:
    label = "slime"

    def __init__(self, obj, depsgraph, batch):
        self.object_name = obj.name
        entry = live.ensure(obj, depsgraph)
        self.sim_ref = weakref.ref(entry.sim)
        self.batch = batch
        self.dabs = []  # (brush, count or None for an erase)
        self.added = self.removed = 0
        self.message = ""

    def _sim(self):
        entry = live.get(self.object_name)
        sim = self.sim_ref()
        if entry is None or sim is None or entry.sim is not sim:
            raise BrushError("The simulation was reset or rebuilt since this slime stroke: "
                             "there is nothing left to undo.")
        if entry.baking:
            raise BrushError(live.bake_running_message(entry, "Cannot change the agents"))
        return entry, sim

    def dab(self, obj, settings, hit):
        entry, sim = self._sim()
        species = min(int(settings.species), int(entry.config["species_count"])) - 1
        brush = _brush_dict(obj, settings, hit, species, settings.erase)
        if settings.erase:
            self.removed += sim.erase_agents(brush, self.batch)
            self.dabs.append((brush, None))
        else:
            sim.add_agents(brush, int(settings.agents_per_dab), self.batch)
            self.added += int(settings.agents_per_dab)
            self.dabs.append((brush, int(settings.agents_per_dab)))
        entry.stats = sim.get_stats()

    def finish(self, obj):
        return bool(self.dabs)

    def undo(self):
        entry, sim = self._sim()
        sim.undo_agents(self.batch)
        entry.stats = sim.get_stats()
        return ""

    def redo(self):
        entry, sim = self._sim()
        for brush, count in self.dabs:
            if count is None:
                sim.erase_agents(brush, self.batch)
            else:
                sim.add_agents(brush, count, self.batch)
        entry.stats = sim.get_stats()
        return ""


def _empty_record(empty):
    return {"name": empty.name, "matrix": [tuple(row) for row in empty.matrix_world],
            "display_type": empty.empty_display_type,
            "display_size": empty.empty_display_size,
            "properties": {key: empty[key] for key in (convert.FOOD_STRENGTH_PROPERTY,
                                                       convert.FOOD_AMOUNT_PROPERTY)
                           if key in empty.keys()},
            "collections": [c.name for c in empty.users_collection]}


def _create_empty(record, fallback_collection):
    empty = bpy.data.objects.new(record["name"], None)
    empty.matrix_world = Matrix(record["matrix"])
    empty.empty_display_type = record["display_type"]
    empty.empty_display_size = record["display_size"]
    for key, value in record["properties"].items():
        empty[key] = value
    linked = False
    for name in record["collections"]:
        collection = bpy.data.collections.get(name)
        if collection is not None:
            collection.objects.link(empty)
            linked = True
    if not linked and fallback_collection is not None:
        fallback_collection.objects.link(empty)
    record["name"] = empty.name  # Blender may have renamed it
    return empty


def _remove_empty(name):
    empty = bpy.data.objects.get(name)
    if empty is not None and empty.type == 'EMPTY':
        bpy.data.objects.remove(empty, do_unlink=True)


def ensure_food_collection(obj, context):
    settings = obj.moldtex
    collection = settings.food_collection
    if collection is None:
        collection = bpy.data.collections.new(f"Moldtex Food {obj.name}")
        context.scene.collection.children.link(collection)
        settings.food_collection = collection
    return collection


class _FoodEdit:
    label = "food"

    def __init__(self, obj, context):
        self.object_name = obj.name
        self.collection_name = ensure_food_collection(obj, context).name
        self.added = []    # records of the Empties created
        self.removed = []  # records of the Empties deleted
        self.message = ""

    def dab(self, obj, settings, hit):
        collection = bpy.data.collections.get(self.collection_name)
        if collection is None:
            raise BrushError("The Food collection is gone: pick or create another.")
        centre = Vector(hit["world"])
        if settings.erase:
            radius = settings.radius
            for empty in [o for o in collection.all_objects if o.type == 'EMPTY']:
                if (empty.matrix_world.translation - centre).length <= radius:
                    self.removed.append(_empty_record(empty))
                    bpy.data.objects.remove(empty, do_unlink=True)
            return
        sources, _dropped = live.food_from_settings(obj)
        if len(sources) >= engine.MAX_FOOD_SOURCES:
            self.message = (f"The Food collection already has {engine.MAX_FOOD_SOURCES} "
                            f"sources, the most the simulation uses: erase some first.")
            return
        empty = bpy.data.objects.new("Food", None)
        empty.empty_display_type = 'SPHERE'
        empty.empty_display_size = max(settings.radius * 0.5, 1e-4)
        empty.location = centre
        empty[convert.FOOD_STRENGTH_PROPERTY] = float(settings.food_strength)
        empty[convert.FOOD_AMOUNT_PROPERTY] = float(settings.food_amount)
        collection.objects.link(empty)
        self.added.append(_empty_record(empty))

    def finish(self, obj):
        return bool(self.added or self.removed)

    def undo(self):
        collection = bpy.data.collections.get(self.collection_name)
        for record in self.added:
            _remove_empty(record["name"])
        for record in self.removed:
            _create_empty(record, collection)
        return ""

    def redo(self):
        collection = bpy.data.collections.get(self.collection_name)
        for record in self.removed:
            _remove_empty(record["name"])
        for record in self.added:
            _create_empty(record, collection)
        return ""


def repair_settings(settings):
    """Sets brush enums holding a value this version does not know (a file from another
    version) back to their defaults, with a note on the console; returns the notes."""
    notes = repair_enums(settings)
    for note in notes:
        print(f"Moldtex brush: {note}")
    return notes


class Stroke:
    """One press-drag-release of the brush (or one moldtex.brush_stroke call)."""

    def __init__(self, context, obj):
        self.obj_name = obj.name
        self.context = context
        settings = context.scene.moldtex_brush
        repair_settings(settings)
        self.target = settings.target
        self.last_centre = None
        if self.target in FIELD_CHANNELS:
            if obj.moldtex.fields_source != 'IMAGE':
                raise BrushError("Fields come from vertex groups or attributes for this "
                                 "object: paint those (Weight Paint mode), or set the "
                                 "Fields source to Image to use the Moldtex brush.")
            if obj.type == 'MESH' and len(obj.data.uv_layers) == 0:
                raise BrushError(f"The Fields image is laid out by the UV map, and "
                                 f"'{obj.name}' has none: add one (UV ▸ Smart UV Project), "
                                 f"or paint the fields as vertex groups (Weight Paint "
                                 f"mode) and pick them as the Fields source.")
            live.check_not_baking(obj, "Cannot paint fields")
            self.edit = _FieldsEdit(obj, ensure_fields_image(obj),
                                    FIELD_CHANNELS[self.target])
        elif self.target == 'SLIME':
            live.check_not_baking(obj, "Cannot paint slime")
            record = history(obj.name)
            self.edit = _SlimeEdit(obj, context.evaluated_depsgraph_get(),
                                   record.next_batch)
            record.next_batch = record.next_batch % engine.MAX_BRUSH_BATCH + 1
        else:
            self.edit = _FoodEdit(obj, context)

    def dab(self, origin, direction, force=False):
        """Casts the ray and paints if it hits (and, within a stroke, the brush moved at
        least DAB_SPACING radii). Returns the hit, or None on a miss."""
        obj = bpy.data.objects.get(self.obj_name)
        if obj is None:
            raise BrushError(f"The object '{self.obj_name}' is gone.")
        hit = cast(obj, self.context.evaluated_depsgraph_get(), origin, direction)
        if hit is None:
            return None
        settings = self.context.scene.moldtex_brush
        centre = Vector(hit["world"])
        if (not force and self.last_centre is not None
                and (centre - self.last_centre).length < DAB_SPACING * settings.radius):
            return hit
        self.last_centre = centre
        self.edit.dab(obj, settings, hit)
        return hit

    def finish(self):
        """Ends the stroke and records it; returns a message for the user or ""."""
        obj = bpy.data.objects.get(self.obj_name)
        if obj is None:
            return ""
        if self.edit.finish(obj):
            history(self.obj_name).push(self.edit)
        return self.edit.message


def undo(obj):
    """Undoes the object's last stroke; returns (done, message)."""
    record = _histories.get(obj.name)
    if record is None or not record.undo:
        return False, "Nothing to undo."
    edit = record.undo.pop()
    try:
        message = edit.undo()
    except (BrushError, engine.EngineError) as error:
        return False, str(error)
    record.redo.append(edit)
    return True, message or f"Undid a {edit.label} stroke."


def redo(obj):
    record = _histories.get(obj.name)
    if record is None or not record.redo:
        return False, "Nothing to redo."
    edit = record.redo.pop()
    try:
        message = edit.redo()
    except (BrushError, engine.EngineError) as error:
        return False, str(error)
    record.undo.append(edit)
    return True, message or f"Redid a {edit.label} stroke."


USER_ERRORS = (BrushError, MeshExportError, engine.EngineError)


def register():
    bpy.utils.register_class(MoldtexBrushSettings)
    bpy.types.Scene.moldtex_brush = bpy.props.PointerProperty(type=MoldtexBrushSettings)


def unregister():
    forget()
    del bpy.types.Scene.moldtex_brush
    bpy.utils.unregister_class(MoldtexBrushSettings)
