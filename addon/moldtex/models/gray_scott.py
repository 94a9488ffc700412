# SPDX-License-Identifier: GPL-3.0-or-later
"""Gray-Scott reaction-diffusion: its settings (obj.moldtex.reaction), their conversion
to the core's moldtex_reaction_params, and what the image shows (V in R, U in G)."""

import bpy
from bpy.props import FloatProperty, IntProperty

from .. import engine
from ..settings import events, units
from ..settings.common import RESET_NOTE
from ..ui import layout as ui_layout
from .base import Model

# The panel's short labels of these settings.
LABELS = {"feed": "Feed", "kill": "Kill", "diffusion_u": "Spread U", "diffusion_v": "Spread V",
          "seed_count": "Seeds", "display_range": "Display"}


def _params_changed(self, context):
    events.changed(self.id_data, "params")


def _reset_changed(self, context):
    # Nothing to push: the panel shows that a Reset is needed.
    pass


def _display_range_changed(self, context):
    events.changed(self.id_data, "display_range")


class MoldtexReaction(bpy.types.PropertyGroup):
    """Parameters of the Gray-Scott model. Diffusion rates and the seed radius are in
    pattern units (see Pattern Scale): the classic pixel-unit values (D_u 0.2, D_v 0.1)
    give the textbook patterns with one pattern unit as the pixel."""
    feed: FloatProperty(
        name="Feed", default=0.037, min=0.0, max=1.0, soft_min=0.01, soft_max=0.1,
        precision=4, step=0.1,
        description="Feed (F): how fast U is replenished, per second. With Kill it picks "
                    "the pattern: spots (0.03, 0.062), labyrinth (0.037, 0.06), "
                    "dividing spots (0.0367, 0.0649), worms (0.078, 0.061)",
        update=_params_changed)
    kill: FloatProperty(
        name="Kill", default=0.06, min=0.0, max=1.0, soft_min=0.04, soft_max=0.07,
        precision=4, step=0.1,
        description="Kill (k): how fast V is removed, per second",
        update=_params_changed)
    diffusion_u: FloatProperty(
        name="Diffusion U", default=0.2, min=0.0, max=1e6, soft_min=0.01, soft_max=1.0,
        precision=3,
        description="Diffusion U (D_u): how fast U spreads, in pattern units² per second "
                    "(see Pattern Scale). Twice Diffusion V in the classic patterns; "
                    "larger rates give larger features",
        update=_params_changed)
    diffusion_v: FloatProperty(
        name="Diffusion V", default=0.1, min=0.0, max=1e6, soft_min=0.005, soft_max=0.5,
        precision=3,
        description="Diffusion V (D_v): how fast V spreads, in pattern units² per second",
        update=_params_changed)
    time_step: FloatProperty(
        name="Time Step", default=1.0, min=0.01, max=100.0, soft_min=0.1, soft_max=4.0,
        precision=2, unit='TIME_ABSOLUTE',
        description="Time Step: simulated seconds per step. The core sub-steps as "
                    "stability needs, so a larger step only runs the pattern faster "
                    "(up to its own cost)",
        update=_params_changed)
    seed_count: IntProperty(
        name="Seeds", default=64, min=1, max=1024,
        description="Seeds: how many small disks of V start the pattern (where the "
                    "Start's Spawn Map says, with that start; else anywhere)." + RESET_NOTE,
        update=_reset_changed)
    seed_radius: FloatProperty(
        name="Seed Radius", default=5.0, min=0.01, max=1e6, soft_min=1.0, soft_max=50.0,
        description="Seed Radius: radius of each starting disk, in pattern units (see "
                    "Pattern Scale)." + RESET_NOTE,
        update=_reset_changed)
    display_range: FloatProperty(
        name="Display Range", default=0.5, min=0.01, max=10.0, soft_min=0.1, soft_max=1.0,
        description="Display Range: the V shown at the top of the colour ramp (0 at its "
                    "bottom). The live image and baked files hold V itself",
        update=_display_range_changed)


def params_from_settings(settings, area):
    """The core's moldtex_reaction_params (Gray-Scott) for settings on a surface of
    `area` mesh units²: diffusion rates from pattern units² to mesh units², the seed
    radius from pattern units. Raises engine.EngineError when the pattern unit is not
    known."""
    reaction = settings.reaction
    unit = units.known_pattern_unit(settings, area)
    return {
        "feed": float(reaction.feed),
        "kill": float(reaction.kill),
        "diffusion_u": float(reaction.diffusion_u) * unit * unit,
        "diffusion_v": float(reaction.diffusion_v) * unit * unit,
        "time_step": float(reaction.time_step),
        "seed_count": int(reaction.seed_count),
        "seed_radius": float(reaction.seed_radius) * unit,
    }


def reset_key(settings):
    """What a Gray-Scott simulation takes only at Reset: the seeds' count and radius,
    and what turns the radius into mesh units (the pattern scale settings); None for
    the other models."""
    return (int(settings.reaction.seed_count), float(settings.reaction.seed_radius),
            float(settings.pattern_scale), units.enum_or(settings, "pattern_scale_mode", 'OBJECT'),
            float(settings.pattern_length))


class _Panel(ui_layout.ModelPanel):
    model_key = "GRAY_SCOTT"


_PANEL_LABELS = {**ui_layout.LABELS, **LABELS}  # (merged once, not at every draw)


def _prop(column, data, name, **kwargs):
    ui_layout.prop(column, data, name, labels=_PANEL_LABELS, **kwargs)


class MOLDTEX_PT_reaction(_Panel, bpy.types.Panel):
    bl_label = "Reaction"
    bl_idname = "MOLDTEX_PT_reaction"

    def draw(self, context):
        obj = context.active_object
        settings = obj.moldtex
        reaction = settings.reaction
        layout = self.layout
        ui_layout.draw_pattern_unit(layout, context, obj, "rates below are in units² / s")
        column = ui_layout.split(layout)
        for name in ("feed", "kill", "diffusion_u", "diffusion_v", "time_step"):
            _prop(column, reaction, name)
        column = ui_layout.split(layout)
        column.label(text="Applied on Reset", icon='FILE_REFRESH')
        _prop(column, reaction, "seed_count")
        _prop(column, reaction, "seed_radius", text="Radius")
        _prop(ui_layout.split(layout), reaction, "display_range")


class GrayScott(Model):
    key = "GRAY_SCOTT"
    number = 2
    engine_id = engine.MODEL_GRAY_SCOTT
    label = "Gray-Scott"
    description = ("Gray-Scott reaction-diffusion: two chemicals U and V react and diffuse "
                   "over the surface into spots, stripes or worms; no agents. The image "
                   "shows V")
    cli_name = "gray-scott"
    settings_name = "reaction"
    settings_class = MoldtexReaction
    domains = (engine.DOMAIN_TEXTURE, engine.DOMAIN_INTRINSIC)
    has_agents = False
    display_channel = 'R'  # V in R, U in G
    map_keys = ("diffusion_rate", "feed", "kill")
    labels = LABELS
    panels = (MOLDTEX_PT_reaction,)
    simulated_time = True
    start_note = ("Gray-Scott: no agents or species; its seeds start where the Spawn field "
                  "says (Start: Spawn Map), else anywhere.")
    slime_note = ("Gray-Scott: each dab seeds V in the live simulation (erase clears it; "
                  "Reset starts over).")
    preset_alias = "r"
    preset_fields = ("feed", "kill", "diffusion_u", "diffusion_v", "time_step", "seed_count",
                     "seed_radius", "display_range")

    def create_arguments(self, settings, area):
        return {"reaction": params_from_settings(settings, area)}

    def push_params(self, sim, settings, area):
        # (the seeds' count and radius wait for Reset: reset_key says so)
        sim.set_reaction_params(params_from_settings(settings, area))

    def reset_key(self, settings):
        return reset_key(settings)

    def display_maximum(self, settings):
        return max(1e-6, float(settings.reaction.display_range))


    def stats_rows(self, stats):
        # coverage = mean V, presence = the area share where V > 0.1.
        return [("Mean V", f"{stats['coverage']:.3f}"),
                ("V > 0.1", f"{100.0 * stats['presence']:.1f} %")]


MODEL = GrayScott()
