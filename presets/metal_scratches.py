# Moldtex preset "metal scratches": sparse, long, nearly straight bright scratches on
# dark metal (momas-paper.md Fig. 11, "metal incisions"). Few agents that hardly turn
# and look far ahead, narrow sensors, fast evaporation and almost no diffusion: each
# agent keeps to its own line. Coverage (Eq. 1) on a 512² plane about 0.5.
# Look: Sparse, long, nearly straight bright scratches on dark metal.
import bpy
obj = bpy.context.object
s = obj.moldtex
s.model = 'MOMAS'
s.movement_speed = 2.0
s.turn_speed = 2.0
s.vision_distance = 2.0
s.vision_angle = 8.0
s.evaporation_rate = 0.8
s.diffusion_rate = 0.5
s.deposit = 1.0
s.substeps = 3
s.agent_count = s.scaled_agent_count(4000)  # agents on 512 x 512 pattern units
s.apply_ramp([
    (0.00, (0.060, 0.062, 0.068, 1.0)),  # dark brushed metal
    (0.60, (0.090, 0.092, 0.100, 1.0)),
    (0.90, (0.500, 0.510, 0.530, 1.0)),
    (1.00, (0.900, 0.910, 0.930, 1.0)),  # bright fresh scratch
], interpolation='LINEAR')
