# SPDX-License-Identifier: GPL-3.0-or-later
"""MoMaS (momas-paper.md Algorithm 1): agents move a fixed step each tick and leave
pheromone in [0, 1]. Its settings are the object's own (obj.moldtex: agents, pheromone,
species, units), since the other agent model shares the species and start settings."""

import bpy

from .. import engine
from ..ui import layout as ui_layout
from .base import Model


class _Panel(ui_layout.ModelPanel):
    model_key = "MOMAS"


def _prop(column, data, name, **kwargs):
    ui_layout.prop(column, data, name, **kwargs)


class MOLDTEX_PT_agents(_Panel, bpy.types.Panel):
    bl_label = "Agents"
    bl_idname = "MOLDTEX_PT_agents"

    def draw(self, context):
        settings = context.active_object.moldtex
        units = ui_layout.split(self.layout)
        _prop(units, settings, "pattern_units")
        ui_layout.draw_pattern_scale(units, settings, settings.pattern_units == 'SURFACE')
        _prop(units, settings, "time_step")
        column = ui_layout.split(self.layout)
        for name in ("movement_speed", "turn_speed", "vision_distance", "vision_angle_ui",
                     "sensor_size"):
            _prop(column, settings, name)


class MOLDTEX_PT_pheromone(_Panel, bpy.types.Panel):
    bl_label = "Pheromone"
    bl_idname = "MOLDTEX_PT_pheromone"

    def draw(self, context):
        settings = context.active_object.moldtex
        column = ui_layout.split(self.layout)
        for name in ("evaporation_rate", "diffusion_rate", "deposit", "substeps"):
            _prop(column, settings, name)


class MoMaS(Model):
    key = "MOMAS"
    number = 0
    engine_id = engine.MODEL_MOMAS
    label = "MoMaS"
    description = ("MoMaS (momas-paper.md): agents move a fixed step each tick and leave "
                   "pheromone in [0, 1] that blurs and evaporates")
    cli_name = "momas"
    pattern_lengths = True
    scaled_presets = True
    species_params = True
    panels = (MOLDTEX_PT_agents, MOLDTEX_PT_pheromone)


MODEL = MoMaS()
