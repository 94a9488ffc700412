# SPDX-License-Identifier: GPL-3.0-or-later
"""What the add-on asks of a model: the few things that differ between models, each
with the answer most models give. A model module (models/<name>.py) makes one instance
of a subclass, MODEL, and models/__init__.py lists it; nothing else in the add-on names
a model.

  key, number       the Model menu's identifier and the number a .blend stores for it
  engine_id         engine.MODEL_*
  label, description, cli_name ("--model" of the command line)
  settings_name     obj.moldtex.<settings_name>: the model's own PropertyGroup
  settings_class    (registered by models.register, before the object's settings)
  domains           the engine.DOMAIN_* it runs on
  has_agents        False: no agents, so no species, agent count or seeds of agents
  pattern_lengths   True: its lengths follow the object's pattern unit (MoMaS in
                    surface units sends the core a length_unit)
  display_channel   the image channel that holds what the ramp shows (None: the image
                    is grey, one value per species)
  preset_alias, preset_fields
                    a preset file writes the model's own settings as
                    <alias>.<field> = value (alias = obj.moldtex.<settings_name>)
  labels, panels    its settings' short labels in the sidebar, its own sub-panels
                    (drawn after the main panel, in models.MODELS' order)
  simulated_time    True: a rate-based model whose stats show the simulated seconds
  species_params    True: each species has its own agent settings (else the model's
                    apply to every species, species_note says so)
  start_note, slime_note
                    what the Species & Start panel and the Slime brush say about it
  map_keys          the parameter maps it reads (maps/spec.py keys, in MAPS' order)
  scaled_presets    True: a preset's agent count is per 512² pattern units and scales
                    to the object (looks/scaling.py); else the count is kept as it is

The methods take the object's settings (obj.moldtex) and, where the core needs lengths
in mesh units, the surface's 3D area in mesh units².
"""

from .. import engine


class Model:
    key = ""
    number = 0
    engine_id = None
    label = ""
    description = ""
    cli_name = ""
    settings_name = None
    settings_class = None
    domains = (engine.DOMAIN_TEXTURE,)
    has_agents = True
    pattern_lengths = False
    display_channel = None
    preset_alias = None
    preset_fields = ()
    scaled_presets = False
    map_keys = ()
    labels = {}
    panels = ()
    simulated_time = False
    species_params = False
    species_note = ""
    start_note = ""
    slime_note = ""

    def create_arguments(self, settings, area):
        """Keyword arguments of engine.Simulation beyond config and params (its own
        parameters). Raises engine.EngineError in words for the user."""
        return {}

    def push_params(self, sim, settings, area):
        """Gives a running simulation the model's own parameters."""

    def reset_key(self, settings):
        """What only Reset takes of the model's own settings (compared by needs_reset),
        or None."""
        return None

    def display_maximum(self, settings):
        """The image value shown at the top of the colour ramp."""
        return 1.0

    def agents_changed(self, settings):
        """The agent or species count changed (it takes effect on Reset)."""

    def after_build(self, entry, obj, sim, surface_info, depsgraph):
        """A new simulation (not yet entry's) on a surface of surface_info (engine
        Surface.info) got its fields and maps; returns what to store on entry (attribute
        name -> value)."""
        return {}

    def after_push(self, entry, obj):
        """entry's simulation got the current parameters."""

    def same_mesh(self, entry, obj, depsgraph):
        """An undo or depsgraph update found the mesh unchanged: refresh what reads the
        mesh's data besides its shape."""

    def stats_rows(self, stats):
        """The stats box's rows that measure the pattern: [(label, text)]. Most agent
        models read MoMaS' Eq. 1: coverage and presence."""
        return [("Coverage", f"{100.0 * stats['coverage']:.1f} %"),
                ("Presence", f"{100.0 * stats['presence']:.1f} %")]

    def draw_setup(self, column, settings):
        """The model's own rows at the head of the Simulation sub-panel."""
