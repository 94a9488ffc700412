# Moldtex preset "lava rivers": glowing orange rivers through dark rock (momas-paper.md
# Fig. 11). Fast agents with many substeps cut wide continuous channels. Coverage
# (Eq. 1) on a 512² plane: 0.46 after 300 steps, about 0.34 once settled. Tip: feed
# the ramp's colour into Emission too for a glow.
# Look: Glowing orange rivers through dark rock: fast agents cut wide continuous channels.
import bpy
obj = bpy.context.object
s = obj.moldtex
s.model = 'MOMAS'
s.movement_speed = 2.0
s.turn_speed = 20.0
s.vision_distance = 2.0
s.vision_angle = 45.0
s.evaporation_rate = 0.3
s.diffusion_rate = 20.0
s.deposit = 1.0
s.substeps = 3
s.agent_count = s.scaled_agent_count(150000)  # agents on 512 x 512 pattern units
s.apply_ramp([
    (0.00, (0.015, 0.012, 0.012, 1.0)),  # dark rock
    (0.30, (0.040, 0.020, 0.015, 1.0)),
    (0.50, (0.350, 0.030, 0.005, 1.0)),  # cooling red crust
    (0.75, (1.000, 0.200, 0.010, 1.0)),  # orange
    (0.92, (1.000, 0.380, 0.030, 1.0)),
    (1.00, (1.000, 0.550, 0.080, 1.0)),  # yellow-orange core
], interpolation='LINEAR')
