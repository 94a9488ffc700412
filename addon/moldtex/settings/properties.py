# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-object settings (bpy.types.Object.moldtex), saved in the .blend.

Parameters (speeds, vision, evaporation, ...) go to a running simulation at once
through their update callbacks (not while a bake runs: the bake keeps the parameters it
started with). Config settings (resolution, agent count, seed, UV map,
backend) shape the simulation itself and take effect on Reset or Start.

The Backend chooser lists this machine's OpenCL devices, which differ between machines,
so it stores nothing itself: its get/set map it onto plain saved properties
(backend_type and the device's indices and names). A file saved with a device this
machine lacks then reads as Auto, and sim.convert.backend_note() says why, instead of Blender
showing an invalid enum value.
"""

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty,
                       FloatVectorProperty, IntProperty, PointerProperty, StringProperty)

from .. import engine, models
from ..colour import material
from ..looks import scaling
from ..maps.settings import MoldtexMaps
from ..sim import convert
from . import events
from .common import PATH_OPTIONS, RESET_NOTE, angle_ui
from .enums import enum_value

MAX_THREADS = 256  # the core refuses more (moldtex_sim_set_params)

# Bake file formats: identifier -> engine.IMAGE_* (bake/sequence.py maps them).
BAKE_FORMAT_ITEMS = [
    ("EXR_HALF", "OpenEXR Half", "16-bit float OpenEXR, one channel (small, plenty for a "
                                 "texture: 11 significant bits)"),
    ("EXR_FLOAT", "OpenEXR Float", "32-bit float OpenEXR, one channel: the exact pheromone"),
    ("PNG8", "PNG 8-bit", "8-bit greyscale PNG (smallest; 256 levels)"),
    ("PNG16", "PNG 16-bit", "16-bit greyscale PNG"),
]

# The numbers are what a .blend stores: keep them when adding sizes (128 came last).
RESOLUTION_ITEMS = [
    ("128", "128 × 128", "Pheromone texture of 128 × 128 texels (quick previews)", 6),
    ("256", "256 × 256", "Pheromone texture of 256 × 256 texels", 0),
    ("512", "512 × 512", "Pheromone texture of 512 × 512 texels", 1),
    ("1024", "1024 × 1024", "Pheromone texture of 1024 × 1024 texels", 2),
    ("2048", "2048 × 2048", "Pheromone texture of 2048 × 2048 texels", 3),
    ("4096", "4096 × 4096", "Pheromone texture of 4096 × 4096 texels", 4),
    ("8192", "8192 × 8192", "Pheromone texture of 8192 × 8192 texels (uses much memory)",
     5),
]

# Simulated texels per texture texel and axis (moldtex_sim_config.detail).
DETAIL_ITEMS = [
    ("AUTO", "Auto",
     "2× or 4× while the simulation has under about two texels per pattern unit (2× up "
     "to 4096² simulated, 4× up to 1024²): at one texel per unit a UV sphere's poles "
     "come out thin", 0),
    ("1", "1×", "Simulate on the texture's own texels", 1),
    ("2", "2×", "Simulate at twice the resolution; the texture is its mean, 2 × 2 texels "
     "per texel", 2),
    ("4", "4×", "Simulate at four times the resolution (16 × the memory and more time)", 3),
]


def _push_params(self, context):
    # self is the object's settings or one species' settings: both belong to the object.
    events.changed(self.id_data, "params")


def _config_changed(self, context):
    # Nothing to push: the panel shows that a Reset is needed.
    pass


def _species_count_changed(self, context):
    # Gives every species up to the new count its own settings (saved), so the panel
    # can show them; the simulation takes the count on Reset. U counts the agents of
    # one species (Eq. 5 per species).
    ensure_species(self)
    _agents_changed(self, context)


def _fields_changed(self, context):
    events.changed(self.id_data, "fields")
    events.changed(self.id_data, "show_fields")


def _show_fields_changed(self, context):
    events.changed(self.id_data, "show_fields")


# Display colours of species 1..4 (red, green, blue, yellow: the image's channels).
SPECIES_COLORS = ((1.0, 0.25, 0.05), (0.1, 0.9, 0.2), (0.15, 0.35, 1.0), (1.0, 0.85, 0.1))

SEED_SHAPE_ITEMS = [
    ("RANDOM", "Random", "Agents everywhere, uniformly by area (never inside walls of the "
                         "Fields)", 0),
    ("SPAWN_MAP", "Spawn Map", "Agents where the Fields' spawn weight is high (the "
                               "image's red channel or the Spawn attribute; more agents "
                               "where higher)", 1),
    ("CIRCLE", "Circle", "Agents on a circle around the 3D cursor (measured on the "
                         "surface), heading inwards", 2),
    ("BIG_BANG", "Big Bang", "All agents at the 3D cursor, heading every way", 3),
    ("STARBURST", "Starburst", "Agents on rays from the 3D cursor, out to the radius, "
                               "heading outwards", 4),
]


# The numbers are what a .blend stores; files from before this setting read as IMAGE.
FIELDS_SOURCE_ITEMS = [
    ("IMAGE", "Image", "A Fields image painted in the object's UV space: red = spawn, "
                       "green = walls, blue = attractors", 0),
    ("ATTRIBUTES", "Attributes", "Vertex groups or painted attributes (Float or Color, "
                                 "per vertex or face corner) of the mesh after its "
                                 "modifiers, named per field", 1),
]


def ensure_species(settings):
    """Makes settings.species hold at least species_count entries; a new entry starts
    with the object's agent settings and the paper's competing attractions."""
    species = settings.species
    while len(species) < settings.species_count:
        index = len(species)
        item = species.add()
        item.name = f"Species {index + 1}"
        for name in ("movement_speed", "turn_speed", "vision_distance", "vision_angle",
                     "deposit"):
            setattr(item, name, getattr(settings, name))
        item.attraction = tuple(1.0 if k == index else -1.0 for k in range(4))
        item.color = SPECIES_COLORS[index % len(SPECIES_COLORS)]


class MoldtexSpecies(bpy.types.PropertyGroup):
    """Behaviour of one species (used when Species is 2 or more)."""
    movement_speed: FloatProperty(
        name="Movement Speed", default=1.0, min=0.0, max=64.0, soft_min=1.0, soft_max=2.0,
        description="Movement Speed: texels an agent of this species travels per step",
        update=_push_params)
    turn_speed: FloatProperty(
        name="Turn Speed", default=20.0, min=0.0, max=1000.0, soft_min=10.0, soft_max=50.0,
        description="Turn Speed: how fast agents of this species turn towards what "
                    "attracts them",
        update=_push_params)
    vision_distance: FloatProperty(
        name="Vision Distance", default=1.0, min=0.0, max=50.0, soft_min=0.4, soft_max=2.0,
        description="Vision Distance: how far ahead this species' sensors are, in units "
                    "of 10 texels",
        update=_push_params)
    vision_angle: FloatProperty(
        name="Vision Angle", default=30.0, min=0.0, max=180.0, soft_min=10.0,
        soft_max=50.0, precision=1,
        description="Vision Angle: angle between the front and side sensors of this "
                    "species, in degrees",
        update=_push_params)
    vision_angle_ui: angle_ui(
        "vision_angle", "Vision Angle: angle between the front and side sensors of this "
                        "species")
    deposit: FloatProperty(
        name="Deposit", default=1.0, min=0.0, max=1.0,
        description="Pheromone this species leaves in its own trail", update=_push_params)
    attraction: FloatVectorProperty(
        name="Attraction", size=4, default=(1.0, -1.0, -1.0, -1.0), min=-1.0, max=1.0,
        description="How much this species follows (+1) or avoids (-1) the trail of "
                    "species 1, 2, 3 and 4", update=_push_params)
    color: FloatVectorProperty(
        name="Color", subtype='COLOR', size=3, default=(1.0, 0.25, 0.05), min=0.0, max=1.0,
        description="Colour of this species in the material Set Up Material makes (run "
                    "it again after changing)")


# The models' own settings (obj.moldtex.<Model.settings_name>) are in models/: the Model
# menu lists them in models.MODELS' order, with the numbers a .blend stores.
MODEL_ITEMS = models.enum_items()


def _labels(names):
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _agents_changed(self, context):
    # The agent count (or the species count, which splits it) enters U: with Keep U on
    # the deposit rate follows at once; the simulation takes the count on Reset.
    models.of_key(enum_value(self, "model")).agents_changed(self)


def _model_changed(self, context):
    # Takes effect on Reset (a new simulation); the material's display range follows
    # the simulation's model, so nothing to do here either.
    pass


BACKEND_AUTO_VALUE = 0
BACKEND_CPU_VALUE = 1
_DEVICE_VALUE_BASE = 2  # item number of OpenCL device i (engine list index) is 2 + i

BACKEND_TYPE_ITEMS = [
    ("AUTO", "Auto", "OpenCL on a GPU if there is one, otherwise the CPU"),
    ("CPU", "CPU", "All cores of this machine"),
    ("OPENCL", "OpenCL", "The OpenCL device given by opencl_platform/opencl_device"),
]

# Blender keeps only pointers to the strings of dynamic enum items: the list must stay
# referenced from Python (or Blender shows garbage and can crash), so it lives here and
# is rebuilt only when the device list changes.
_backend_items = []
_backend_items_key = None


def device_identifier(device):
    return f"OPENCL_{device['platform_index']}_{device['device_index']}"


def backend_items(self, context):
    global _backend_items, _backend_items_key
    devices, _reason = engine.opencl_devices()
    key = tuple((d["index"], d["platform_index"], d["device_index"], d["name"],
                 d["platform_name"]) for d in devices)
    if key != _backend_items_key or not _backend_items:
        items = [
            ("AUTO", "Auto", "OpenCL on the first GPU if this machine has one and it "
                             "works, otherwise the CPU (a CPU OpenCL device is not used: "
                             "the native CPU code is as fast there)", BACKEND_AUTO_VALUE),
            ("CPU", "CPU", "All cores of this machine (see Threads)", BACKEND_CPU_VALUE),
        ]
        names = [d["name"] for d in devices]
        for device in devices:
            label = device["name"]
            if names.count(label) > 1:
                label = f"{label} ({device['platform_name']})"
            kind = "GPU" if device["is_gpu"] else "CPU device"
            memory = device["global_memory_bytes"] / 2**30
            items.append((device_identifier(device), f"OpenCL: {label}",
                          f"{device['name']} on {device['platform_name']} ({kind}, "
                          f"{memory:.1f} GiB)",
                          _DEVICE_VALUE_BASE + device["index"]))
        _backend_items, _backend_items_key = items, key
    return _backend_items


def _get_backend(self):
    if self.backend_type == 'CPU':
        return BACKEND_CPU_VALUE
    if self.backend_type == 'OPENCL':
        device, _note = convert.find_opencl_device(self)
        if device is not None:
            return _DEVICE_VALUE_BASE + device["index"]
    # Auto, or a device this machine does not have (live.backend_note says so).
    return BACKEND_AUTO_VALUE


def _set_backend(self, value):
    if value == BACKEND_CPU_VALUE:
        self.backend_type = 'CPU'
        return
    if value >= _DEVICE_VALUE_BASE:
        devices, _reason = engine.opencl_devices()
        for device in devices:
            if _DEVICE_VALUE_BASE + device["index"] == value:
                self.opencl_platform = device["platform_index"]
                self.opencl_device = device["device_index"]
                self.opencl_device_name = device["name"]
                self.opencl_platform_name = device["platform_name"]
                self.backend_type = 'OPENCL'
                return
    self.backend_type = 'AUTO'


DOMAIN_ITEMS = [
    ('TEXTURE', "Texture", "The texels of the UV layout (every model)"),
    ('INTRINSIC', "Intrinsic", "An intrinsic Delaunay triangulation of the surface "
                               "(layton-intrinsic-slime.md §3.1): no UV seams or stretch; "
                               + _labels(models.on_domain(engine.DOMAIN_INTRINSIC)).lower()
                               + " models"),
]


class MoldtexSettings(bpy.types.PropertyGroup):
    model: EnumProperty(
        name="Model", items=MODEL_ITEMS, default='MOMAS',
        description="Model: how the agents and the pheromone behave." + RESET_NOTE,
        update=_model_changed)
    domain: EnumProperty(
        name="Domain", items=DOMAIN_ITEMS, default='TEXTURE',
        description="Domain: where the pheromone (or the chemicals) live. The texture's "
                    "texels follow the UV layout; Intrinsic uses a triangulation of the "
                    "surface itself (no UV seams, no UV stretch), still written into the "
                    "same texture. " + _labels(models.on_domain(engine.DOMAIN_INTRINSIC))
                    + " models." + RESET_NOTE,
        update=_config_changed)
    intrinsic_size: FloatProperty(
        name="Triangle Size", default=0.0, min=0.0, max=1e6, soft_max=1.0,
        subtype='DISTANCE',
        description="Triangle Size: the largest circumradius of an intrinsic triangle, a "
                    "length in the scene. 0 = from the texture resolution (about one "
                    "vertex per texel). Smaller: finer and slower." + RESET_NOTE,
        update=_config_changed)
    # Parameter maps and stimuli of the continuous model (maps/settings.py; registered
    # by maps.register() before this class).
    maps: PointerProperty(type=MoldtexMaps)
    # ---- agents (momas-paper.md Table 1) ----
    movement_speed: FloatProperty(
        name="Movement Speed", default=1.0, min=0.0, max=64.0, soft_min=1.0, soft_max=2.0,
        description="Movement Speed (δa): texels an agent travels per step. Larger = "
                    "coarser pattern",
        update=_push_params)
    turn_speed: FloatProperty(
        name="Turn Speed", default=20.0, min=0.0, max=1000.0, soft_min=10.0, soft_max=50.0,
        description="Turn Speed (ϑa): how fast agents turn towards pheromone. Larger = "
                    "the pattern stabilises less",
        update=_push_params)
    vision_distance: FloatProperty(
        name="Vision Distance", default=1.0, min=0.0, max=50.0, soft_min=0.4, soft_max=2.0,
        description="Vision Distance (δs): how far ahead the sensors are, in units of 10 "
                    "texels. Larger = bigger cells",
        update=_push_params)
    vision_angle: FloatProperty(
        name="Vision Angle", default=30.0, min=0.0, max=180.0, soft_min=10.0,
        soft_max=50.0, precision=1,
        description="Vision Angle (ϑs): angle between the front and side sensors, in "
                    "degrees. Larger = thicker trails",
        update=_push_params)
    vision_angle_ui: angle_ui(
        "vision_angle", "Vision Angle (ϑs): angle between the front and side sensors. "
                        "Larger = thicker trails")
    pattern_units: EnumProperty(
        name="Units",
        items=(('SURFACE', "Surface",
                "Pattern lengths are measured on the surface: the same look at any texture "
                "resolution and across UV seams and poles (resolution only sharpens it)"),
               ('TEXELS', "Texels",
                "MoMaS' texel units: lengths are in texels of this resolution, so a higher "
                "resolution gives a finer pattern")),
        default='SURFACE', update=_push_params)
    pattern_scale_mode: EnumProperty(
        name="Pattern Scale Mode",
        items=(('OBJECT', "Object",
                "The pattern unit follows the object's size: Scale × √(area) / 512, so "
                "a look is the same on a 10 cm and a 10 m object"),
               ('LENGTH', "Length",
                "The pattern unit is a fixed length in the scene: a larger object shows "
                "more cells of the same size")),
        default='OBJECT',
        description="Pattern Scale Mode: what the pattern unit (the length every "
                    "pattern length is a multiple of) is measured against",
        update=_push_params)
    pattern_scale: FloatProperty(
        name="Pattern Scale", default=1.0, min=0.01, max=100.0, soft_min=0.25, soft_max=4.0,
        description="Pattern Scale: the pattern unit as a fraction of the object's size "
                    "(1 = √(object area) / 512, a 512² texel of a layout that fills the "
                    "texture). Larger = bigger cells and thicker trails, whatever the "
                    "resolution",
        update=_push_params)
    pattern_length: FloatProperty(
        name="Pattern Length", default=0.005, min=1e-6, max=1e6, soft_min=0.0001,
        soft_max=1.0, subtype='DISTANCE', unit='LENGTH', precision=4,
        description="Pattern Length: the pattern unit as a length in the scene, measured "
                    "on the object as it sits there (its scale applied)",
        update=_push_params)
    time_step: FloatProperty(
        name="Time Step", default=1.0 / 60.0, min=0.001, max=0.25, precision=4,
        unit='TIME_ABSOLUTE',
        description="Time Step: simulated seconds per step (Δt; 1/60 s reproduces the papers). In "
                    "surface units and in the continuous model the result depends on "
                    "simulated time, not on the step count: a smaller step is finer in "
                    "time, not slower in motion (MoMaS agents turn 60 times a simulated "
                    "second at any step). Continuous model: keep it well below the "
                    "turn decision period, the mean lifetime and the activation time",
        update=_push_params)
    sensor_size: IntProperty(
        name="Sensor Size", default=0, min=0, max=4,
        description="Sensor Size: each sensor sums a (2r + 1)² texel square around its point (the "
                    "MoMaS reference's kernel); 0 = the single texel under it. 2 gives "
                    "the paper's Fig. 8c: coverage falls as evaporation rises",
        update=_push_params)
    # ---- pheromone ----
    evaporation_rate: FloatProperty(
        name="Evaporation", default=0.5, min=0.0, max=1000.0, soft_min=0.2, soft_max=1.0,
        description="Evaporation Rate (εd): pheromone lost per second. Larger = smaller "
                    "clusters, less coverage",
        update=_push_params)
    diffusion_rate: FloatProperty(
        name="Diffusion", default=10.0, min=0.0, max=1000.0, soft_min=0.0, soft_max=60.0,
        description="Diffusion Rate: how fast the pheromone blurs, per second",
        update=_push_params)
    deposit: FloatProperty(
        name="Deposit", default=1.0, min=0.0, max=1.0,
        description="Deposit: pheromone an agent leaves behind (the texel becomes at least this)",
        update=_push_params)
    substeps: IntProperty(
        name="Substeps", default=2, min=1, max=64,
        description="Deposits along each move, so fast agents leave unbroken trails",
        update=_push_params)
    # ---- simulation setup (need a reset) ----
    agent_count: IntProperty(
        name="Agents", default=60000, min=1, max=67108864, soft_max=4000000,
        description="Agents: number of agents." + RESET_NOTE,
        update=_agents_changed)
    resolution: EnumProperty(
        name="Resolution", items=RESOLUTION_ITEMS, default="512",
        description="Resolution: size of the pheromone texture." + RESET_NOTE,
        update=_config_changed)
    detail: EnumProperty(
        name="Detail", items=DETAIL_ITEMS, default="AUTO",
        description="Detail (MoMaS in Units: Surface): how many simulated texels span one "
                    "texture texel along each axis. The texture keeps its Resolution and "
                    "shows their mean; the pattern is the same, computed more finely (and "
                    "more slowly). Auto aims at about two simulated texels per pattern "
                    "unit, which a UV sphere's poles need (one texel per unit leaves them "
                    "about 30% thin)." + RESET_NOTE,
        update=_config_changed)
    seed: IntProperty(
        name="Seed", default=0, min=0,
        description="Random seed: the same seed gives the same pattern." + RESET_NOTE,
        update=_config_changed)
    backend: EnumProperty(
        name="Backend", items=backend_items, get=_get_backend, set=_set_backend,
        description="Where the simulation runs. Auto uses OpenCL only on a GPU (on a "
                    "CPU OpenCL device the native CPU code is as fast), otherwise the "
                    "CPU; or pick the CPU or one OpenCL device." + RESET_NOTE,
        update=_config_changed)
    # What the Backend chooser stores (saved; not shown in the panel). Scripts may set
    # backend_type = 'OPENCL' with opencl_platform/opencl_device and an empty
    # opencl_device_name: the indices are then used as they are.
    backend_type: EnumProperty(
        name="Backend Type", items=BACKEND_TYPE_ITEMS, default="AUTO",
        description="Kind of backend the Backend chooser stored." + RESET_NOTE,
        update=_config_changed)
    opencl_platform: IntProperty(
        name="OpenCL Platform", default=0, min=0,
        description="Index of the chosen OpenCL device's platform." + RESET_NOTE,
        update=_config_changed)
    opencl_device: IntProperty(
        name="OpenCL Device", default=0, min=0,
        description="Index of the chosen OpenCL device on its platform." + RESET_NOTE,
        update=_config_changed)
    opencl_device_name: StringProperty(
        name="OpenCL Device Name", default="",
        description="Name of the chosen OpenCL device, to find it again on another "
                    "machine or after drivers change (empty = use the indices as they "
                    "are)." + RESET_NOTE,
        update=_config_changed)
    opencl_platform_name: StringProperty(
        name="OpenCL Platform Name", default="",
        description="Name of the chosen OpenCL device's platform." + RESET_NOTE,
        update=_config_changed)
    uv_map: StringProperty(
        name="UV Map", default="",
        description="UV Map the mold grows in. Empty = the mesh's render UV map (the one "
                    "marked with the camera icon in Object Data ▸ UV Maps)."
                    + RESET_NOTE,
        update=_config_changed)
    # ---- species, starting seeds and fields (momas-paper.md §2.5) ----
    species_count: IntProperty(
        name="Species", default=1, min=1, max=4,
        description="Number of competing species, each with its own trail and settings "
                    "(the image's R, G, B, A channels)." + RESET_NOTE,
        update=_species_count_changed)
    species: CollectionProperty(type=MoldtexSpecies)
    seed_shape: EnumProperty(
        name="Start", items=SEED_SHAPE_ITEMS, default="RANDOM",
        description="Where the agents start." + RESET_NOTE,
        update=_config_changed)
    seed_radius: FloatProperty(
        name="Radius", default=0.5, min=1e-6, max=1e9, soft_min=0.01, soft_max=10.0,
        subtype='DISTANCE', unit='LENGTH',
        description="Radius of the Circle or Starburst, in scene units, measured along "
                    "the surface from the point nearest the 3D cursor." + RESET_NOTE,
        update=_config_changed)
    seed_rays: IntProperty(
        name="Rays", default=8, min=1, max=1024,
        description="Number of Starburst rays." + RESET_NOTE,
        update=_config_changed)
    fields_image: PointerProperty(
        name="Fields", type=bpy.types.Image,
        description="Fields: maze image painted in this object's UV space: red = where agents "
                    "start (Spawn Map), green = walls, blue = attractors (food). Applied "
                    "when picked and on Reset (after painting it, press Reset)",
        update=_fields_changed)
    show_fields: BoolProperty(
        name="Show Fields", default=False,
        description="Lay the Fields image over the pheromone in the Moldtex material "
                    "(walls green, attractors blue, spawn red), e.g. while painting them "
                    "with the brush. Renders show it too while it is on",
        update=_show_fields_changed)
    fields_source: EnumProperty(
        name="Fields Source", items=FIELDS_SOURCE_ITEMS, default='IMAGE',
        description="Where the static fields (spawn weights, walls, attractors) come "
                    "from. Applied when changed and on Reset",
        update=_fields_changed)
    spawn_attribute: StringProperty(
        name="Spawn", default="",
        description="Vertex group, or Float or Color attribute (per vertex or face "
                    "corner; a colour counts by its brightness), whose value is where "
                    "agents start with Start = Spawn Map (more where higher; below 0 "
                    "counts as 0). Empty = none. Applied when changed and on Reset",
        update=_fields_changed)
    obstacle_attribute: StringProperty(
        name="Obstacle", default="",
        description="Vertex group or attribute marking walls no agent enters: where its "
                    "value is above 0.5. Empty = none. Applied when changed and on Reset",
        update=_fields_changed)
    attractor_attribute: StringProperty(
        name="Attractor", default="",
        description="Vertex group or attribute attracting every species, 0 to 1 "
                    "(clamped). Empty = none. Applied when changed and on Reset",
        update=_fields_changed)
    # ---- food (plasmodial-slime-readme.md, "Food Sources") ----
    food_collection: PointerProperty(
        name="Food", type=bpy.types.Collection,
        description="Food Collection: collection whose Empties are food sources (up to 64, by name). Each "
                    "Empty attracts hungry agents to the surface point near it. Custom "
                    "properties of an Empty (Object Properties ▸ Custom Properties): "
                    "'moldtex_strength' = attraction, in scene units² (default 1: full "
                    "pull within 1 unit, weaker as 1/distance² beyond); "
                    "'moldtex_amount' = units of food, one eaten per agent per step, "
                    "refilled on Reset (default -1 = never runs out). Moving an Empty "
                    "moves its food at once")
    hunger_rate: FloatProperty(
        name="Hunger Rate", default=0.0, min=0.0, max=1000.0, soft_min=0.0, soft_max=5.0,
        description="Hunger Rate: hunger agents gain per second (60 steps); hungry agents steer "
                    "towards the nearest food and become sated when they reach it. "
                    "0 = food is ignored",
        update=_push_params)
    food_radius: FloatProperty(
        name="Food Radius", default=0.1, min=0.0, max=1e6, soft_min=0.0, soft_max=1.0,
        subtype='DISTANCE', unit='LENGTH',
        description="Food Radius: distance (scene units, in 3D) from a food Empty within which an "
                    "agent eats",
        update=_push_params)
    # ---- playback ----
    steps_per_update: IntProperty(
        name="Steps per Update", default=0, min=0, max=1000, soft_max=20,
        description="Steps per Update: simulation steps between two updates of the image "
                    "while running. 0 = as many as the machine manages: the mold grows on a "
                    "thread while the viewport redraws (the panel shows steps per second)")
    update_time: IntProperty(
        name="Update Time", default=50, min=5, max=500, subtype='NONE',
        description="Update Time: milliseconds of stepping in one go while running with "
                    "Steps per Update 0: the longest the interface waits for the simulation "
                    "(shorter: more responsive, longer: slightly faster growth)")
    thread_count: IntProperty(
        name="Threads", default=0, min=0, max=MAX_THREADS, soft_max=64,
        description="CPU threads (0 = all cores); the result does not depend on it. "
                    "Unused when the simulation runs on OpenCL",
        update=_push_params)
    image: PointerProperty(
        name="Image", type=bpy.types.Image,
        description="Image that receives the pheromone (made by Set Up Material or the "
                    "first step)")
    preset_name: StringProperty(
        name="Preset", default="",
        description="Name of the look (preset) last applied to this object, shown on "
                    "its preset menu")
    # Colour ramp of the last preset (JSON: [[position, [r, g, b, a]], ...] and the
    # interpolation), used when Set Up Material creates the ramp later.
    ramp_stops: StringProperty(
        name="Preset Ramp", default="", options={'HIDDEN'},
        description="Colour ramp stops of the last preset, for Set Up Material")
    # ---- bake (image sequence, bake/sequence.py) ----
    bake_use_scene_range: BoolProperty(
        name="Scene Frame Range", default=False,
        description="Bake the scene's frame range (Output Properties ▸ Frame Range); off: "
                    "bake from Start to End below")
    bake_frame_start: IntProperty(
        name="Start", default=1, min=0, max=999999,
        description="First frame to bake when not using the scene's frame range")
    bake_frame_end: IntProperty(
        name="End", default=48, min=0, max=999999,
        description="Last frame to bake when not using the scene's frame range")
    bake_steps_per_frame: IntProperty(
        name="Steps per Frame", default=2, min=1, max=100000, soft_max=60,
        description="Steps per Frame: simulation steps between two baked frames (60 steps = 1 s of the paper's "
                    "clock). Frame f shows the mold after (f - start + 1) × this many steps")
    bake_directory: StringProperty(
        name="Output Folder", default="//moldtex_bake/", subtype='DIR_PATH',
        options=PATH_OPTIONS,
        description="Output Folder for the frames, metrics.csv and the checkpoint (// = next to "
                    "the .blend file); created if missing")
    bake_format: EnumProperty(
        name="Format", items=BAKE_FORMAT_ITEMS, default="EXR_HALF",
        description="File format of the baked frames")
    bake_prefix: StringProperty(
        name="File Prefix", default="",
        description="File Prefix: start of every file name, e.g. 'rock_' gives rock_0001.exr (empty = "
                    "the object's name and '_'). Characters other than letters, digits, "
                    "'.', '-' and '_' become '_'")
    bake_resume: BoolProperty(
        name="Resume", default=False,
        description="Continue an interrupted bake from its checkpoint (same mesh, "
                    "settings, frame range and steps per frame) instead of starting over; "
                    "the frames equal those of an uninterrupted bake")

    # ---- helpers for preset files (looks/presets.py); methods, so that a preset needs no
    # import of this add-on (its module name differs between installs) ----
    def scaled_agent_count(self, agents_at_512):
        """Agent count giving the density `agents_at_512` agents have on 512 × 512
        pattern units: per texel of this resolution in Units: Texels, per pattern unit
        (whatever the resolution) in Units: Surface (looks/scaling.py)."""
        return scaling.scaled_agent_count(agents_at_512, scaling.agents_per_preset_agent(self))

    def apply_ramp(self, stops, interpolation='LINEAR'):
        """Sets the Moldtex colour ramp: stops = [(position, (r, g, b, a)), ...]."""
        material.apply_ramp(self.id_data, stops, interpolation)


# Each model's own settings group (registered by models.register() before this class).
for _name, _group in models.settings_groups().items():
    MoldtexSettings.__annotations__[_name] = PointerProperty(type=_group)

CLASSES = (MoldtexSpecies, MoldtexSettings)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.moldtex = PointerProperty(type=MoldtexSettings)


def unregister():
    del bpy.types.Object.moldtex
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
