# Moldtex preset "wood grain": banded browns (momas-paper.md Fig. 1, right).
# The core has no directional bias yet, so the trails do not run along a grain
# direction: the wood look comes mostly from this banded ramp, which turns the
# pheromone's smooth rise and fall around each trail into rings of light and dark
# brown. Coverage (Eq. 1) on a 512² plane: 0.72 after 300 steps, about 0.54 once
# settled.
# Look: Banded browns: rings of light and dark brown around each trail (no grain direction yet).
import bpy
obj = bpy.context.object
s = obj.moldtex
s.model = 'MOMAS'
s.movement_speed = 2.0
s.turn_speed = 10.0
s.vision_distance = 1.2
s.vision_angle = 12.0
s.evaporation_rate = 0.4
s.diffusion_rate = 8.0
s.deposit = 1.0
s.substeps = 2
s.agent_count = s.scaled_agent_count(100000)  # agents on 512 x 512 pattern units
s.apply_ramp([
    (0.00, (0.200, 0.095, 0.035, 1.0)),  # dark brown
    (0.14, (0.380, 0.200, 0.080, 1.0)),  # light band
    (0.28, (0.220, 0.105, 0.040, 1.0)),
    (0.42, (0.420, 0.230, 0.095, 1.0)),
    (0.56, (0.240, 0.115, 0.045, 1.0)),
    (0.70, (0.460, 0.260, 0.110, 1.0)),
    (0.84, (0.260, 0.125, 0.050, 1.0)),
    (1.00, (0.500, 0.290, 0.125, 1.0)),  # pale heartwood
], interpolation='EASE')
