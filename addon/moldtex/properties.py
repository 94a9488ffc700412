# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-object settings (bpy.types.Object.moldtex), saved in the .blend.

Parameters (speeds, vision, evaporation, ...) go to a running simulation at once
through their update callbacks. Config settings (resolution, agent count, seed, UV map)
shape the simulation itself and take effect on Reset or Start.
"""

import bpy
from bpy.props import (EnumProperty, FloatProperty, IntProperty, PointerProperty,
                       StringProperty)

from . import engine, live

_RESET_NOTE = " Takes effect on Reset (or Start)"

RESOLUTION_ITEMS = [
    ("256", "256 × 256", "Pheromone texture of 256 × 256 texels"),
    ("512", "512 × 512", "Pheromone texture of 512 × 512 texels"),
    ("1024", "1024 × 1024", "Pheromone texture of 1024 × 1024 texels"),
    ("2048", "2048 × 2048", "Pheromone texture of 2048 × 2048 texels"),
    ("4096", "4096 × 4096", "Pheromone texture of 4096 × 4096 texels"),
    ("8192", "8192 × 8192", "Pheromone texture of 8192 × 8192 texels (uses much memory)"),
]


def _push_params(self, context):
    obj = self.id_data
    try:
        live.push_params(obj)
    except engine.EngineError as error:
        entry = live.get(obj.name)
        if entry is not None:
            entry.notice = str(error)
        print(f"Moldtex: {error}")


def _config_changed(self, context):
    # Nothing to push: the panel shows that a Reset is needed.
    pass


class MoldtexSettings(bpy.types.PropertyGroup):
    # ---- agents (momas-paper.md Table 1) ----
    movement_speed: FloatProperty(
        name="Movement Speed", default=1.0, min=0.0, max=64.0, soft_min=1.0, soft_max=2.0,
        description="Texels an agent travels per step (δa). Larger = coarser pattern",
        update=_push_params)
    turn_speed: FloatProperty(
        name="Turn Speed", default=20.0, min=0.0, max=1000.0, soft_min=10.0, soft_max=50.0,
        description="How fast agents turn towards pheromone (ϑa). Larger = the pattern "
                    "stabilises less",
        update=_push_params)
    vision_distance: FloatProperty(
        name="Vision Distance", default=1.0, min=0.0, max=50.0, soft_min=0.4, soft_max=2.0,
        description="How far ahead the sensors are, in units of 10 texels (δs). "
                    "Larger = bigger cells",
        update=_push_params)
    vision_angle: FloatProperty(
        name="Vision Angle", default=30.0, min=0.0, max=180.0, soft_min=10.0,
        soft_max=50.0, precision=1,
        description="Angle between the front and side sensors, in degrees (ϑs). "
                    "Larger = thicker trails",
        update=_push_params)
    # ---- pheromone ----
    evaporation_rate: FloatProperty(
        name="Evaporation", default=0.5, min=0.0, max=1000.0, soft_min=0.2, soft_max=1.0,
        description="Pheromone lost per second (εd). Larger = smaller clusters, less "
                    "coverage",
        update=_push_params)
    diffusion_rate: FloatProperty(
        name="Diffusion", default=10.0, min=0.0, max=1000.0, soft_min=0.0, soft_max=60.0,
        description="How fast the pheromone blurs, per second",
        update=_push_params)
    deposit: FloatProperty(
        name="Deposit", default=1.0, min=0.0, max=1.0,
        description="Pheromone an agent leaves behind (the texel becomes at least this)",
        update=_push_params)
    substeps: IntProperty(
        name="Substeps", default=2, min=1, max=64,
        description="Deposits along each move, so fast agents leave unbroken trails",
        update=_push_params)
    # ---- simulation setup (need a reset) ----
    agent_count: IntProperty(
        name="Agents", default=200000, min=1, max=67108864, soft_max=4000000,
        description="Number of agents." + _RESET_NOTE,
        update=_config_changed)
    resolution: EnumProperty(
        name="Resolution", items=RESOLUTION_ITEMS, default="1024",
        description="Size of the pheromone texture." + _RESET_NOTE,
        update=_config_changed)
    seed: IntProperty(
        name="Seed", default=0, min=0,
        description="Random seed: the same seed gives the same pattern." + _RESET_NOTE,
        update=_config_changed)
    uv_map: StringProperty(
        name="UV Map", default="",
        description="UV map the mold grows in (empty = the mesh's active render UV map)."
                    + _RESET_NOTE,
        update=_config_changed)
    # ---- playback ----
    steps_per_update: IntProperty(
        name="Steps per Update", default=2, min=1, max=1000, soft_max=20,
        description="Simulation steps between two updates of the image while running")
    thread_count: IntProperty(
        name="Threads", default=0, min=0, max=1024, soft_max=64,
        description="CPU threads (0 = all cores); the result does not depend on it",
        update=_push_params)
    image: PointerProperty(
        name="Image", type=bpy.types.Image,
        description="Image that receives the pheromone (made by Set Up Material or the "
                    "first step)")


CLASSES = (MoldtexSettings,)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.moldtex = PointerProperty(type=MoldtexSettings)


def unregister():
    del bpy.types.Object.moldtex
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
