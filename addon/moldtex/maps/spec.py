# SPDX-License-Identifier: GPL-3.0-or-later
"""What each parameter map is (no bpy): the table the settings, the sampling and the
panel share.

A map value v (a vertex group's weight, an attribute's value, an image's brightness)
is clamped to [0, 1] and becomes what the core takes (engine.Simulation.set_map):
  multipliers  At 0 + (At 1 - At 0) × v, in [0, 1000], times the parameter there
  stimuli      Strength × v, signed, in units of U (layton-intrinsic-slime.md Eq. 5)
"""

from .. import engine

MULTIPLIER = "MULTIPLIER"
STIMULUS = "STIMULUS"



class MapSpec:
    __slots__ = ("key", "kind", "label", "name", "role", "at0", "at1", "strength",
                 "meaning")

    def __init__(self, key, kind, label, name, role, meaning, at0=1.0, at1=2.0,
                 strength=1.0):
        self.key = key            # property name in settings.maps (maps/settings.py)
        self.kind = kind          # engine.MAP_*
        self.label = label        # the panel's short label (fits the sidebar)
        self.name = name          # the parameter's long name (tooltips, errors)
        self.role = role          # MULTIPLIER or STIMULUS
        self.meaning = meaning    # what the map does, for its tooltip
        self.at0, self.at1, self.strength = at0, at1, strength
        # (which models read it: their Model.map_keys, models/)


# Defaults an artist can read off the panel: a multiplier leaves the parameter as it is
# where nothing is painted (At 0 = 1) and doubles it where fully painted (At 1 = 2);
# Lifetime makes a painted region a sink (At 1 = 0: agents die there at once), Spawn
# makes it the source where agents are reborn (At 0 = 0, At 1 = 1).
MAPS = (
    MapSpec("move_rate", engine.MAP_MOVE_RATE, "Speed", "Move Rate", MULTIPLIER,
            "scales how fast agents walk there"),
    MapSpec("turn_rate", engine.MAP_TURN_RATE, "Turning", "Turn Rate", MULTIPLIER,
            "scales how fast agents turn there"),
    MapSpec("sensor_distance", engine.MAP_SENSOR_DISTANCE, "Sight", "Sensor Distance",
            MULTIPLIER, "scales how far ahead agents sense there (bigger cells)"),
    MapSpec("sensor_angle", engine.MAP_SENSOR_ANGLE, "Angle", "Sensor Angle", MULTIPLIER,
            "scales the angle between the sensors there (thicker trails)"),
    MapSpec("deposit_rate", engine.MAP_DEPOSIT_RATE, "Deposit", "Deposit Rate",
            MULTIPLIER, "scales the pheromone agents lay there (brighter trails)"),
    MapSpec("mean_lifetime", engine.MAP_MEAN_LIFETIME, "Lifetime", "Mean Lifetime",
            MULTIPLIER, "scales how long agents live there; 0 makes a sink: agents "
            "there die at once and are reborn by the Spawn map (or anywhere), even "
            "when Lifetime is 0 (agents otherwise live for ever)", at0=1.0, at1=0.0),
    MapSpec("activation_time", engine.MAP_ACTIVATION_TIME, "Activation",
            "Activation Time", MULTIPLIER,
            "scales how long reborn agents wait before they lay pheromone there"),
    MapSpec("spawn", engine.MAP_SPAWN, "Spawn", "Spawn", MULTIPLIER,
            "weights where agents are reborn after they die (a source): more where "
            "higher; needs turnover (Lifetime above 0, or a Lifetime map sink)",
            at0=0.0, at1=1.0),
    MapSpec("read_stimulus", engine.MAP_READ_STIMULUS, "Lure", "Read Stimulus",
            STIMULUS, "a scent every agent senses on top of the trails, in units of U "
            "(1 = as strong as the uniform steady state; negative repels); it never "
            "spreads or fades", strength=1.0),
    MapSpec("write_stimulus", engine.MAP_WRITE_STIMULUS, "Emitter", "Write Stimulus",
            STIMULUS, "adds pheromone there (negative removes it) at Strength × decay "
            "rate × U per second, which then spreads and decays with the trails (alone "
            "it holds u / U at Strength)", strength=1.0),
    MapSpec("diffusion_rate", engine.MAP_DIFFUSION_RATE, "Diffusion", "Diffusion Rate",
            MULTIPLIER, "scales how fast pheromone (or a reaction's chemicals) spreads "
            "there (Eq. 6's per-cell rate; larger reaction features); 0 on a band makes "
            "a wall nothing crosses"),
    MapSpec("decay_rate", engine.MAP_DECAY_RATE, "Decay", "Decay Rate", MULTIPLIER,
            "scales how fast pheromone fades there (fainter trails where higher)"),
    MapSpec("feed", engine.MAP_FEED, "Feed", "Feed", MULTIPLIER,
            "scales the reaction's feed F there (capped at 1): with the kill map it "
            "moves the pattern between spots, stripes and worms, or switches it off"),
    MapSpec("kill", engine.MAP_KILL, "Kill", "Kill", MULTIPLIER,
            "scales the reaction's kill k there (capped at 1); twice the kill of the "
            "classic looks leaves the surface bare there"),
)


BY_KEY = {spec.key: spec for spec in MAPS}
assert sorted(spec.kind for spec in MAPS) == list(range(engine.MAP_COUNT))
