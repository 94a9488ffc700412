# SPDX-License-Identifier: GPL-3.0-or-later
"""The continuous model (layton-intrinsic-slime.md §3.2): its settings
(obj.moldtex.continuous), their conversion to the core's moldtex_continuous_params, U
(Eq. 5) and Keep U, the bias, and what the image shows (u / U)."""

import array
import math
import zlib

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, StringProperty

from .. import engine
from ..colour import nodes
from ..data.mesh_export import MeshExportError, export_scale
from ..maps import mesh_values
from ..settings import events, units
from ..settings.enums import enum_value
from ..sim import registry
from ..ui import layout as ui_layout
from .base import Model

# The panel's short labels of these settings (time_step is the object's own).
LABELS = {"move_rate": "Speed", "turn_rate": "Turning", "turn_frequency": "Decisions",
          "sensor_distance": "Sight", "sensor_angle": "Angle", "deposit_rate": "Deposit",
          "diffusion_rate": "Diffusion", "decay_rate": "Decay", "display_range": "Display",
          "mean_lifetime": "Lifetime", "activation_time": "Activation",
          "bias_strength": "Strength", "bias_symmetry": "Symmetry", "bias_spawn": "Spawn",
          "bias_direction": "Toward",  # a vector: Blender draws "Toward X", "Y", "Z"
          "bias_source": "Source", "boundary": "Edges", "bias_attribute": "Attribute"}

BOUNDARY_ITEMS = [
    ("REFLECT", "Reflect", "Agents turn back into the surface", 0),
    ("ABSORB", "Absorb", "Agents die where they meet the edge and are reborn (a sink "
                         "along the edges, Fig. 18; the Spawn map says where)", 1),
]

INTEGRATOR_ITEMS = [
    ("AUTO", "Auto", "Forward Euler while 64 sub-steps per step keep it stable, else "
                     "backward Euler", 0),
    ("FORWARD", "Forward", "Forward Euler (Eq. 2), sub-stepped for stability (the core "
                           "refuses more than 256 sub-steps a step)", 1),
    ("BACKWARD", "Backward", "Backward Euler (Eq. 3): stable at any time step, more work "
                             "per step", 2),
]

# Set while Keep U itself writes the deposit rate, so that write is not taken for the
# user's own change (which makes the new deposit rate's U the one to keep).
_keeping_u = False


def keep_u(settings):
    """With Keep U on, sets the deposit rate so that U (Eq. 5) equals the stored target
    for the current agent count, surface area, decay rate, mean lifetime and activation
    time. Returns True if it changed the deposit rate."""
    global _keeping_u
    cont = settings.continuous
    if not cont.keep_u or cont.target_u <= 0.0:
        return False
    rate = deposit_rate_for_target(settings)
    if rate is None or abs(rate - cont.deposit_rate) <= 1e-7 * max(rate, 1e-30):
        return False
    _keeping_u = True
    try:
        cont.deposit_rate = rate
    finally:
        _keeping_u = False
    return True


def _continuous_changed(self, context):
    events.changed(self.id_data, "params")


def _u_input_changed(self, context):
    # Decay rate, mean lifetime or activation time: Eq. 5's inputs besides r_dep.
    if not keep_u(self.id_data.moldtex):
        events.changed(self.id_data, "params")  # (keep_u's write pushed already)


def _deposit_rate_changed(self, context):
    if self.keep_u and not _keeping_u:
        # The user set the deposit: its U is the one to keep from now on.
        self.target_u = u_from_settings(self.id_data.moldtex) or 0.0
    events.changed(self.id_data, "params")


def _keep_u_changed(self, context):
    if self.keep_u:
        self.target_u = u_from_settings(self.id_data.moldtex) or 0.0


def _display_range_changed(self, context):
    events.changed(self.id_data, "display_range")


class MoldtexContinuous(bpy.types.PropertyGroup):
    """Parameters of the continuous model (layton-intrinsic-slime.md Table 1)."""
    # ---- agent ----
    move_rate: FloatProperty(
        name="Move Rate", default=60.0, min=0.0, max=1e6, soft_min=5.0, soft_max=200.0,
        description="Move Rate (v): distance an agent walks per second, in pattern units "
                    "(see Pattern Scale) per second. Larger = longer strands",
        update=_continuous_changed)
    turn_rate: FloatProperty(
        name="Turn Rate", subtype='ANGLE', default=math.radians(720.0), min=0.0,
        max=1e6, soft_min=0.0, soft_max=math.radians(3600.0), precision=0, step=1000,
        description="Turn Rate (ω): how fast an agent turns, in degrees per second; each "
                    "turn decision turns it by ω / f at once",
        update=_continuous_changed)
    turn_frequency: FloatProperty(
        name="Turn Frequency", default=20.0, min=1e-3, max=1e6, soft_min=1.0,
        soft_max=60.0,
        description="Turn Frequency (Turn Decision Frequency fi): turn decisions per "
                    "second. Few decisions = straight runs and sharp turns",
        update=_continuous_changed)
    sensor_distance: FloatProperty(
        name="Sensor Distance", default=12.0, min=0.0, max=1e6, soft_min=1.0,
        soft_max=60.0,
        description="Sensor Distance (d): how far ahead the sensors are, along the "
                    "surface, in pattern units (see Pattern Scale). Larger = bigger cells",
        update=_continuous_changed)
    sensor_angle: FloatProperty(
        name="Sensor Angle", subtype='ANGLE', default=math.radians(30.0),
        min=-math.pi, max=math.pi, soft_min=math.radians(-90.0),
        soft_max=math.radians(90.0), precision=1, step=100,
        description="Sensor Angle (θ): angle between the front and side sensors. "
                    "Negative = chemo-repulsion (agents turn away from pheromone)",
        update=_continuous_changed)
    # ---- pheromone ----
    deposit_rate: FloatProperty(
        name="Deposit Rate", default=1.0, min=0.0, max=1e12, soft_min=0.0,
        soft_max=100.0, precision=4,
        description="Deposit Rate (r_dep): pheromone an agent lays per second, spread "
                    "evenly along its path. With Keep U on it follows U: set it, and "
                    "its U becomes the one kept",
        update=_deposit_rate_changed)
    diffusion_rate: FloatProperty(
        name="Diffusion Rate", default=20.0, min=0.0, max=1e6, soft_min=0.0,
        soft_max=200.0,
        description="Diffusion Rate (r_dif): how fast pheromone spreads over the "
                    "surface, in pattern units² per second (see Pattern Scale)",
        update=_continuous_changed)
    decay_rate: FloatProperty(
        name="Decay Rate", default=5.0, min=0.0, max=1e6, soft_min=0.1, soft_max=30.0,
        description="Decay Rate (r_dec): fraction of the pheromone lost per second. "
                    "Larger = thinner, sharper trails",
        update=_u_input_changed)
    keep_u: BoolProperty(
        name="Keep U", default=False,
        description="Keep U: hold the uniform steady-state concentration U (Eq. 5) at "
                    "its current value: when the agent count, species, surface area, "
                    "decay rate, mean lifetime or activation time change, the deposit "
                    "rate follows (the paper's way to keep a look across meshes and "
                    "agent counts)",
        update=_keep_u_changed)
    target_u: FloatProperty(
        name="Target U", default=0.0, min=0.0, options={'HIDDEN'},
        description="Target U: the U (Eq. 5, in the core's mesh units) that Keep U holds")
    display_range: FloatProperty(
        name="Display Range", default=3.0, min=0.01, max=1e4, soft_min=0.5, soft_max=10.0,
        description="Display Range: the u / U shown at the top of the colour ramp (0 at "
                    "its bottom; 1 is the uniform steady state). The live image and "
                    "baked EXR files hold u / U itself",
        update=_display_range_changed)
    # ---- turnover ----
    mean_lifetime: FloatProperty(
        name="Mean Lifetime", default=0.0, min=0.0, max=1e6, soft_min=0.0, soft_max=10.0,
        precision=3, unit='TIME_ABSOLUTE',
        description="Mean Lifetime (τ̄): agents die after a random time of this mean and "
                    "start again anywhere on the surface, which keeps the pattern "
                    "uniform. 0 = agents live for ever",
        update=_u_input_changed)
    activation_time: FloatProperty(
        name="Activation Time", default=0.0, min=0.0, max=1e6, soft_min=0.0,
        soft_max=10.0, precision=3, unit='TIME_ABSOLUTE',
        description="Activation Time (Deposit Activation Time t_a): a new agent lays "
                    "no pheromone until it is this old, so reborn agents do not blot "
                    "the pattern",
        update=_u_input_changed)
    # ---- directional bias (layton-intrinsic-slime.md §3.3, Fig. 6) ----
    bias_strength: FloatProperty(
        name="Bias Strength", default=0.0, min=0.0, max=1e6, soft_min=0.0,
        soft_max=20.0,
        description="Bias Strength: how fast agents turn toward the bias direction, per "
                    "second (times the angle to it). 0 = no bias",
        update=_continuous_changed)
    bias_symmetry: IntProperty(
        name="Bias Symmetry", default=1, min=1, max=6,
        description="Bias Symmetry (n): agents turn toward the nearest of n copies of "
                    "the direction, 360° / n apart on each face: 1 pulls one way, 2 "
                    "aligns the trails along the direction both ways, 4 along it and "
                    "across it",
        update=_continuous_changed)
    bias_spawn: BoolProperty(
        name="Spawn Along Bias", default=False,
        description="Spawn Along Bias: agents reborn by turnover start facing one of the "
                    "bias directions of their face (the paper's sources, Fig. 8), even "
                    "with Strength 0; off: any heading",
        update=_continuous_changed)
    bias_direction: FloatVectorProperty(
        name="Bias Direction", subtype='XYZ', size=3, default=(1.0, 0.0, 0.0),
        description="Bias Direction: the direction agents are pulled toward, in the "
                    "object's local axes; projected onto each face (faces it is normal "
                    "to feel no pull)",
        update=_continuous_changed)
    bias_source: EnumProperty(
        name="Bias Source", default='DIRECTION',
        items=(('DIRECTION', "Direction", "One direction for the whole object (Bias "
                "Direction)"),
               ('ATTRIBUTE', "Attribute", "A vector per face from a Face vector attribute "
                "(Map Tools ▸ Gradient to Bias writes one); its length weights the "
                "strength")),
        description="Bias Source: where the bias directions come from",
        update=_continuous_changed)
    bias_attribute: StringProperty(
        name="Bias Attribute", default="moldtex_bias",
        description="Bias Attribute: Face vector attribute holding each face's bias "
                    "vector in the object's local axes (length 1 = full strength)",
        update=_continuous_changed)
    boundary: EnumProperty(
        name="Open Edges", items=BOUNDARY_ITEMS, default='REFLECT',
        description="Open Edges: what agents do where the mesh ends (its open boundary "
                    "edges)",
        update=_continuous_changed)
    # ---- simulation ----
    integrator: EnumProperty(
        name="Integrator", items=INTEGRATOR_ITEMS, default='AUTO',
        description="Integrator: how the pheromone's diffusion-decay equation is "
                    "stepped",
        update=_continuous_changed)
    # 3D area (mesh units², as the core measures it) of the surface this object last
    # simulated: U is known without a simulation (the panel, Keep U before a Reset).
    surface_area: FloatProperty(
        name="Surface Area", default=0.0, min=0.0, options={'HIDDEN'},
        description="Surface Area: area of the mesh last simulated, in mesh units², "
                    "for U")


# ---- Backend chooser ------------------------------------------------------------------

# ---- U (layton-intrinsic-slime.md Eq. 5) --------------------------------------------

def agents_per_species(settings):
    """Agents of species 0 at the configured count (agent i belongs to species i %
    species_count): the N of Eq. 5 as the core counts it."""
    count = max(1, int(settings.species_count))
    return -(-int(settings.agent_count) // count)


def u_from_settings(settings, area=None, compute=True):
    """U (Eq. 5) that the settings give on obj's surface (area: mesh units², default
    surface_area(obj, compute)); None when the area is not known. +inf without decay."""
    obj = settings.id_data
    if area is None:
        area = units.surface_area(obj, compute) if obj is not None else None
    if not area:
        return None
    cont = settings.continuous
    return engine.u_metric(agents_per_species(settings), float(cont.deposit_rate),
                           float(cont.decay_rate), area, float(cont.activation_time),
                           float(cont.mean_lifetime))


def deposit_rate_for_target(settings, area=None):
    """The deposit rate giving the stored target U (Keep U) with the current agent
    count, area, decay rate, mean lifetime and activation time; None if none can."""
    obj = settings.id_data
    if area is None:
        area = units.surface_area(obj) if obj is not None else None
    if not area:
        return None
    cont = settings.continuous
    return engine.deposit_rate_for_u(float(cont.target_u), agents_per_species(settings),
                                     float(cont.decay_rate), area,
                                     float(cont.activation_time), float(cont.mean_lifetime))


INTEGRATORS = {"AUTO": engine.INTEGRATOR_AUTO, "FORWARD": engine.INTEGRATOR_FORWARD,
               "BACKWARD": engine.INTEGRATOR_BACKWARD}


def params_from_settings(settings, area):
    """The core's moldtex_continuous_params for settings on a surface of `area` mesh
    units²: lengths from pattern units to mesh units (pattern_unit), the sensor angle
    in degrees. Raises engine.EngineError when the pattern unit is not known (no
    area in Object mode)."""
    cont = settings.continuous
    unit = units.known_pattern_unit(settings, area)
    return {
        "move_rate": float(cont.move_rate) * unit,
        "turn_rate": float(cont.turn_rate),
        "turn_frequency": float(cont.turn_frequency),
        "sensor_distance": float(cont.sensor_distance) * unit,
        "sensor_angle": math.degrees(float(cont.sensor_angle)),
        "deposit_rate": float(cont.deposit_rate),
        "diffusion_rate": float(cont.diffusion_rate) * unit * unit,
        "decay_rate": float(cont.decay_rate),
        "mean_lifetime": float(cont.mean_lifetime),
        "activation_time": float(cont.activation_time),
        "time_step": float(settings.time_step),
        "integrator": INTEGRATORS.get(enum_value(cont, "integrator"),
                                      engine.INTEGRATOR_AUTO),
        "bias_strength": float(cont.bias_strength),
        "bias_symmetry": int(cont.bias_symmetry),
        "bias_spawn": 1 if cont.bias_spawn else 0,
        "boundary": (engine.BOUNDARY_ABSORB if enum_value(cont, "boundary") == 'ABSORB'
                     else engine.BOUNDARY_REFLECT),
    }


def bias_direction_in_mesh(obj):
    """The continuous model's Bias Direction (object axes) in the exported mesh's
    coordinates (mesh_export: a non-uniform object scale is applied to them, so a
    direction along the surface scales with it), normalised; None when it is zero or
    the bias is off (Bias Strength 0)."""
    cont = obj.moldtex.continuous
    if not (cont.bias_strength > 0.0 or cont.bias_spawn):
        return None
    direction = [float(v) for v in cont.bias_direction]
    scale = export_scale(obj)
    if scale is not None:
        direction = [d * float(k) for d, k in zip(direction, scale)]
    length = math.sqrt(sum(d * d for d in direction))
    if not (length > 0.0 and math.isfinite(length)):
        return None
    return tuple(d / length for d in direction)


def bias_vectors(direction, triangle_count):
    """moldtex_sim_set_bias' vectors: `direction` for each of the triangles (array('f')
    of triangle_count * 3), or None for None (no bias)."""
    if direction is None:
        return None
    return array.array("f", direction) * int(triangle_count)


def bias_from_settings(obj, triangle_count, depsgraph=None):
    """(key, vectors) of the bias obj's settings ask for: the Bias Direction on every
    triangle, or with Bias Source Attribute each face's vector of that Face attribute
    (maps/mesh_values.py); vectors None = no bias. Raises engine.EngineError."""
    cont = obj.moldtex.continuous
    if getattr(cont, "bias_source", 'DIRECTION') == 'ATTRIBUTE':
        if not (cont.bias_strength > 0.0 or cont.bias_spawn):
            return (None, triangle_count), None
        try:
            vectors = mesh_values.bias_vectors_from_attribute(obj, depsgraph, cont.bias_attribute,
                                                              triangle_count)
        except MeshExportError as error:
            raise engine.EngineError(str(error), engine.ERROR_INVALID_ARGUMENT) from None
        return (("ATTRIBUTE", zlib.crc32(vectors.tobytes())), triangle_count), vectors
    direction = bias_direction_in_mesh(obj)
    return (direction, triangle_count), bias_vectors(direction, triangle_count)


def push_bias(entry, obj, sim=None, depsgraph=None):
    """Gives the simulation the bias vectors of obj's settings when they differ from
    the last ones it got (entry.bias_key). sim: a new simulation, not yet entry's,
    which always gets them; its key is returned for the caller to store."""
    fresh = sim is not None
    sim = sim if fresh else entry.sim
    key, vectors = bias_from_settings(obj, sim.triangle_count, depsgraph)
    if not fresh and key == entry.bias_key:
        return key
    sim.set_bias(vectors)
    if not fresh:
        entry.bias_key = key
    return key


def note_u_area(sim, settings, triangle_area):
    """Stores the area U's Eq. 5 uses on this simulation (the core's A: the 3D area of
    the island texels, the PDE's cells, which the triangles' area approaches as the
    resolution grows), read back from the U the core reports; then, with Keep U on,
    sets the deposit rate for the target U on it (a new mesh, resolution or agent
    count) and gives it to the simulation."""
    cont = settings.continuous
    stats = sim.get_stats()
    u_value = stats.get("u_metric", 0.0)
    rate = float(cont.deposit_rate)
    agents = agents_per_species(settings)
    area = triangle_area
    if 0.0 < u_value < math.inf and rate > 0.0 and cont.decay_rate > 0.0:
        # U = N r_dep alive / (r_dec A) with the float32 values the core holds.
        core = sim.get_continuous_params()
        alive = (math.exp(-core["activation_time"] / core["mean_lifetime"])
                 if core["mean_lifetime"] > 0.0 else 1.0)
        area = agents * core["deposit_rate"] * alive / (core["decay_rate"] * u_value)
    if area and area > 0.0 and math.isfinite(area):
        cont.surface_area = area
    if keep_u(settings):
        sim.set_continuous_params({"deposit_rate": float(cont.deposit_rate)})


# ---- panels --------------------------------------------------------------------------

class _Panel(ui_layout.ModelPanel):
    model_key = "CONTINUOUS"


_PANEL_LABELS = {**ui_layout.LABELS, **LABELS}  # (merged once, not at every draw)


def _prop(column, data, name, **kwargs):
    ui_layout.prop(column, data, name, labels=_PANEL_LABELS, **kwargs)


def _u_text(obj):
    """ "U 0.0123" from the live continuous simulation's stats, else from the settings
    (Eq. 5 with the last known area); "" when neither is known."""
    entry = registry.get(obj.name)
    stats = entry.stats if entry is not None and entry.has_sim else None
    if stats and entry.config.get("model") == engine.MODEL_CONTINUOUS and "u_metric" in stats:
        value = stats["u_metric"]
    else:
        value = u_from_settings(obj.moldtex, compute=False)
    if value is None:
        return ""
    return "U ∞ (no decay)" if value == float("inf") else f"U {value:.4g}"


# The continuous model's sub-panels follow layton-intrinsic-slime.md Table 1: Agent,
# Pheromone, Turnover; its Simulation group (time step, integrator) heads the
# Simulation sub-panel.

class MOLDTEX_PT_continuous_agents(_Panel, bpy.types.Panel):
    bl_label = "Agents"
    bl_idname = "MOLDTEX_PT_continuous_agents"

    def draw(self, context):
        obj = context.active_object
        settings = obj.moldtex
        layout = self.layout
        ui_layout.draw_pattern_unit(layout, context, obj, "lengths below are in units")
        column = ui_layout.split(layout)
        for name in ("move_rate", "turn_rate", "turn_frequency", "sensor_distance",
                     "sensor_angle"):
            _prop(column, settings.continuous, name)
        if settings.continuous.sensor_angle < 0.0:
            ui_layout.wrapped(layout, "Negative angle: agents turn away from pheromone "
                             "(chemo-repulsion).", icon='INFO')


class MOLDTEX_PT_continuous_pheromone(_Panel, bpy.types.Panel):
    bl_label = "Pheromone"
    bl_idname = "MOLDTEX_PT_continuous_pheromone"

    def draw(self, context):
        obj = context.active_object
        cont = obj.moldtex.continuous
        layout = self.layout
        column = ui_layout.split(layout)
        for name in ("deposit_rate", "diffusion_rate", "decay_rate", "keep_u"):
            _prop(column, cont, name)
        text = _u_text(obj)
        if text:
            kept = " (kept)" if cont.keep_u else ""
            ui_layout.wrapped(layout, f"{text}{kept}: the uniform steady state, Eq. 5",
                     icon='INFO')
        else:
            ui_layout.wrapped(layout, "U (Eq. 5) is known after Reset: it needs the surface's "
                             "area.", icon='INFO')
        _prop(ui_layout.split(layout), cont, "display_range")
        if (nodes.moldtex_node(obj, nodes.TEXTURE_NODE) is not None
                and nodes.moldtex_node(obj, nodes.RANGE_NODE) is None):
            ui_layout.wrapped(layout, "The material predates the display range: press Set Up "
                             "Material to show u / U.", icon='ERROR')


class MOLDTEX_PT_continuous_turnover(_Panel, bpy.types.Panel):
    bl_label = "Turnover"
    bl_idname = "MOLDTEX_PT_continuous_turnover"

    def draw(self, context):
        cont = context.active_object.moldtex.continuous
        layout = self.layout
        column = ui_layout.split(layout)
        _prop(column, cont, "mean_lifetime")
        sub = column.column(align=True)
        sub.active = cont.mean_lifetime > 0.0
        _prop(sub, cont, "activation_time")
        _prop(column, cont, "boundary")
        if cont.mean_lifetime <= 0.0:
            ui_layout.wrapped(layout, "Lifetime 0: agents live for ever (no turnover).",
                     icon='INFO')


class MOLDTEX_PT_continuous_bias(_Panel, bpy.types.Panel):
    bl_label = "Bias"
    bl_idname = "MOLDTEX_PT_continuous_bias"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        cont = context.active_object.moldtex.continuous
        layout = self.layout
        column = ui_layout.split(layout)
        _prop(column, cont, "bias_strength")
        sub = column.column(align=True)
        sub.active = cont.bias_strength > 0.0 or cont.bias_spawn
        _prop(sub, cont, "bias_symmetry")
        _prop(sub, cont, "bias_source")
        if cont.bias_source == 'ATTRIBUTE':
            sub.prop_search(cont, "bias_attribute", context.active_object.data, "attributes",
                            text=LABELS["bias_attribute"])
        else:
            _prop(sub, cont, "bias_direction")
        _prop(column, cont, "bias_spawn")
        if cont.bias_strength <= 0.0 and not cont.bias_spawn:
            ui_layout.wrapped(layout, "Strength 0: no pull (agents turn only toward pheromone).",
                     icon='INFO')
        elif cont.bias_source == 'ATTRIBUTE':
            ui_layout.wrapped(layout, "Each face's vector (object axes) from the attribute; "
                             "Map Tools ▸ Gradient to Bias writes one.", icon='INFO')
        else:
            ui_layout.wrapped(layout, "Direction in the object's axes, along each face.",
                     icon='INFO')


class Continuous(Model):
    key = "CONTINUOUS"
    number = 1
    engine_id = engine.MODEL_CONTINUOUS
    label = "Continuous"
    description = ("Continuous model (layton-intrinsic-slime.md §3.2): rates per second, a "
                   "diffusion-decay PDE, deposits along each path and agent turnover; the "
                   "image shows u / U (1 = the uniform steady state)")
    cli_name = "continuous"
    settings_name = "continuous"
    settings_class = MoldtexContinuous
    domains = (engine.DOMAIN_TEXTURE, engine.DOMAIN_INTRINSIC)
    map_keys = ("move_rate", "turn_rate", "sensor_distance", "sensor_angle", "deposit_rate",
                "mean_lifetime", "activation_time", "spawn", "read_stimulus",
                "write_stimulus", "diffusion_rate", "decay_rate")
    simulated_time = True
    species_note = ("Continuous model: its settings apply to every species; each keeps "
                    "its colour and attractions.")
    labels = LABELS
    panels = (MOLDTEX_PT_continuous_agents, MOLDTEX_PT_continuous_pheromone,
              MOLDTEX_PT_continuous_turnover, MOLDTEX_PT_continuous_bias)
    # (Keep U is set last in a preset, so that the U it keeps is the preset's own.)
    preset_alias = "c"
    preset_fields = ("move_rate", "turn_rate", "turn_frequency", "sensor_distance",
                     "sensor_angle", "deposit_rate", "diffusion_rate", "decay_rate",
                     "mean_lifetime", "activation_time", "integrator", "display_range")

    def create_arguments(self, settings, area):
        return {"continuous": params_from_settings(settings, area)}

    def push_params(self, sim, settings, area):
        sim.set_continuous_params(params_from_settings(settings, area))

    def display_maximum(self, settings):
        return max(1e-6, float(settings.continuous.display_range))

    def agents_changed(self, settings):
        keep_u(settings)

    def after_build(self, entry, obj, sim, surface_info, depsgraph):
        note_u_area(sim, obj.moldtex, surface_info.get("area"))
        return {"bias_key": push_bias(entry, obj, sim, depsgraph)}

    def after_push(self, entry, obj):
        push_bias(entry, obj)

    def same_mesh(self, entry, obj, depsgraph):
        if getattr(obj.moldtex.continuous, "bias_source", "") == 'ATTRIBUTE':
            push_bias(entry, obj, depsgraph=depsgraph)  # the attribute may have changed


    def stats_rows(self, stats):
        # U (Eq. 5) and the mean concentration in units of it (1 = the uniform steady
        # state, reached after a few 1 / decay rate).
        u_value = stats.get("u_metric", 0.0)
        mean = stats.get("mean_concentration", 0.0)
        return [("U", "∞" if u_value == float("inf") else f"{u_value:.4g}"),
                ("Mean", f"{mean / u_value:.3f} U" if 0.0 < u_value < float("inf")
                 else f"{mean:.4g}")]

    def draw_setup(self, column, settings):
        _prop(column, settings, "time_step")
        _prop(column, settings.continuous, "integrator")


MODEL = Continuous()
