# SPDX-License-Identifier: GPL-3.0-or-later
"""How a preset's agent count scales to an object: a preset counts agents for 512 × 512
pattern units. Reads settings only; registers nothing."""

from ..settings import units

REFERENCE_RESOLUTION = units.REFERENCE_RESOLUTION  # preset counts are for 512² pattern units
MAX_AGENTS = 67108864


def agents_per_preset_agent(settings, area=None):
    """How many agents `settings` (a MoMaS look) needs for each agent a preset counts:
    a preset's count is for REFERENCE_RESOLUTION² pattern units over the object, which
    Units: Texels makes texels of a 512² texture and Units: Surface √(area) / 512 × 1
    (Pattern Scale 1). So in texel units the count follows the resolution (4× agents per
    doubling, the same agents per texel), and in surface units it does not: there the
    pattern unit, not the texel, is fixed on the model, and 4× agents at 1024² grew a
    denser network (marble on a torus, 300 steps, 2 seeds: dark share 0.08 at 1024² with
    240 000 agents against 0.12-0.14 at 512² and 1024² with 60 000). It follows the
    pattern unit instead: Pattern Scale 2 makes cells twice as long, so a quarter of the
    agents keeps as many per cell. area: the surface's area (mesh units²), needed for
    Scale: Length only (units.surface_area when None; 1 when unknown)."""
    if getattr(settings, "pattern_units", 'SURFACE') != 'SURFACE':
        return (int(settings.resolution) / REFERENCE_RESOLUTION) ** 2
    if getattr(settings, "pattern_scale_mode", 'OBJECT') != 'LENGTH':
        return 1.0 / float(settings.pattern_scale) ** 2
    obj = settings.id_data
    if area is None and obj is not None:
        area = units.surface_area(obj)
    unit = units.pattern_unit(settings, area)
    if not area or area <= 0.0 or unit <= 0.0:
        return 1.0
    return area / (REFERENCE_RESOLUTION * unit) ** 2


def scaled_agent_count(agents_at_512, factor):
    """`agents_at_512` agents of a preset times `factor` (agents_per_preset_agent),
    bounded to the core's limits."""
    count = round(float(agents_at_512) * float(factor))
    return max(1, min(MAX_AGENTS, int(count)))
