# Moldtex preset "starbursts" (continuous model): layton-intrinsic-slime.md Fig. 9f, a
# large sensor distance with fast turnover (mean lifetime 0.2 s, activation time
# 0.4 s). Agents see far and gather into bright knots, and the reborn ones streaming in
# draw fine rays around each. On Suzanne at 512², 60 000 agents: knots after 3 s, held
# at 10 s (std of u/U 1.1, 29 % of the surface below 0.25 U).
# Look: Continuous model: bright knots with fine radiating rays, like sea urchins or starbursts (large sensor distance, fast turnover).
import math
import bpy
obj = bpy.context.object
s = obj.moldtex
c = s.continuous
s.model = 'CONTINUOUS'
c.keep_u = False  # (set last: the U it keeps is this look's)
c.move_rate = 90.0
c.turn_rate = math.radians(720.0)
c.turn_frequency = 20.0
c.sensor_distance = 50.0
c.sensor_angle = math.radians(30.0)
c.deposit_rate = 1.0
c.diffusion_rate = 5.0
c.decay_rate = 5.0
c.mean_lifetime = 0.2
c.activation_time = 0.4
c.integrator = 'AUTO'
c.display_range = 3.0
s.time_step = 1.0 / 60.0
s.agent_count = 60000  # the continuous model's look does not depend on the resolution
c.keep_u = True
s.apply_ramp([
    (0.00, (0.015, 0.005, 0.030, 1.0)),  # dark violet
    (0.15, (0.080, 0.020, 0.120, 1.0)),
    (0.45, (0.700, 0.250, 0.050, 1.0)),  # ember
    (0.80, (1.000, 0.750, 0.200, 1.0)),
    (1.00, (1.000, 0.950, 0.750, 1.0)),  # bright core
], interpolation='LINEAR')
