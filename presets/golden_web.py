# Moldtex preset "golden web": a fine gold network on black (momas-paper.md Fig. 1,
# middle). Fast turning, wide sensors and little diffusion keep the trails thin and
# crisp. Coverage (Eq. 1) on a 512² plane: 0.39 after 300 steps, about 0.28 once the
# network has settled.
# Look: A fine gold network on black: fast turning and wide sensors keep the trails thin and crisp.
import bpy
obj = bpy.context.object
s = obj.moldtex
s.model = 'MOMAS'
s.movement_speed = 1.5
s.turn_speed = 30.0
s.vision_distance = 1.5
s.vision_angle = 40.0
s.evaporation_rate = 0.5
s.diffusion_rate = 2.0
s.deposit = 1.0
s.substeps = 2
s.agent_count = s.scaled_agent_count(80000)  # agents on 512 x 512 pattern units
s.apply_ramp([
    (0.00, (0.000, 0.000, 0.000, 1.0)),  # black
    (0.45, (0.004, 0.002, 0.000, 1.0)),
    (0.60, (0.300, 0.130, 0.010, 1.0)),  # deep gold
    (0.85, (0.650, 0.350, 0.040, 1.0)),
    (1.00, (0.800, 0.500, 0.100, 1.0)),  # bright gold
], interpolation='LINEAR')
