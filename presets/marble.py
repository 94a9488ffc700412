# Moldtex preset "marble": grey veins in off-white stone (momas-paper.md Fig. 1, left).
# Slow, far-sighted agents with narrow sensors lay long thin trails; strong diffusion
# softens them into veins. Coverage (Eq. 1) on a 512² plane: 0.54 after 300 steps,
# about 0.30 once the network has settled.
# Look: Grey veins in off-white stone: long thin trails softened into veins by strong diffusion.
import bpy
obj = bpy.context.object
s = obj.moldtex
s.model = 'MOMAS'
s.movement_speed = 1.0
s.turn_speed = 15.0
s.vision_distance = 2.0
s.vision_angle = 22.0
s.evaporation_rate = 0.25
s.diffusion_rate = 30.0
s.deposit = 1.0
s.substeps = 2
s.agent_count = s.scaled_agent_count(60000)  # agents on 512 x 512 pattern units
s.apply_ramp([
    (0.00, (0.82, 0.80, 0.76, 1.0)),  # off-white stone
    (0.45, (0.80, 0.78, 0.74, 1.0)),
    (0.70, (0.52, 0.52, 0.54, 1.0)),  # grey vein
    (0.88, (0.33, 0.33, 0.36, 1.0)),
    (1.00, (0.22, 0.22, 0.25, 1.0)),  # dark vein core
], interpolation='LINEAR')
