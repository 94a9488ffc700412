# Moldtex preset "moss": dense, short-sighted agents form small clumpy cells, green on
# dark bark (momas-paper.md supplementary Fig. 4). Coverage (Eq. 1) on a 512² plane:
# 0.39 after 300 steps, about 0.37 once settled.
# Look: Small clumpy green cells on dark bark, from dense, short-sighted agents.
import bpy
obj = bpy.context.object
s = obj.moldtex
s.model = 'MOMAS'
s.movement_speed = 1.0
s.turn_speed = 40.0
s.vision_distance = 0.4
s.vision_angle = 50.0
s.evaporation_rate = 1.0
s.diffusion_rate = 6.0
s.deposit = 1.0
s.substeps = 1
s.agent_count = s.scaled_agent_count(200000)  # agents on 512 x 512 pattern units
s.apply_ramp([
    (0.00, (0.050, 0.030, 0.018, 1.0)),  # dark bark brown
    (0.12, (0.060, 0.050, 0.020, 1.0)),
    (0.30, (0.070, 0.140, 0.025, 1.0)),  # dark moss
    (0.65, (0.180, 0.360, 0.050, 1.0)),
    (1.00, (0.320, 0.520, 0.090, 1.0)),  # moss green
], interpolation='LINEAR')
