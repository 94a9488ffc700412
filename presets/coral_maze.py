# Moldtex preset "coral maze" (continuous model): layton-intrinsic-slime.md Fig. 9b,
# a small move and turn rate with agent turnover (mean lifetime and activation time
# 1 s). Slow, short-sighted agents lay a dense maze of narrow winding ridges. On Suzanne
# at 512², 60 000 agents: the maze covers the surface after 3 s and holds its scale at
# 10 s (std of u/U 1.7, 26 % of the surface above U).
# Look: Continuous model: a dense maze of narrow winding coral ridges (small move and turn rates, turnover).
import math
import bpy
obj = bpy.context.object
s = obj.moldtex
c = s.continuous
s.model = 'CONTINUOUS'
c.keep_u = False  # (set last: the U it keeps is this look's)
c.move_rate = 15.0
c.turn_rate = math.radians(240.0)
c.turn_frequency = 20.0
c.sensor_distance = 6.0
c.sensor_angle = math.radians(30.0)
c.deposit_rate = 1.0
c.diffusion_rate = 4.0
c.decay_rate = 3.0
c.mean_lifetime = 1.0
c.activation_time = 1.0
c.integrator = 'AUTO'
c.display_range = 3.0
s.time_step = 1.0 / 60.0
s.agent_count = 60000  # the continuous model's look does not depend on the resolution
c.keep_u = True
s.apply_ramp([
    (0.00, (0.010, 0.030, 0.080, 1.0)),  # deep water
    (0.15, (0.020, 0.070, 0.140, 1.0)),
    (0.40, (0.600, 0.180, 0.120, 1.0)),  # coral red
    (0.75, (0.950, 0.450, 0.300, 1.0)),
    (1.00, (1.000, 0.800, 0.650, 1.0)),  # pale tips
], interpolation='EASE')
