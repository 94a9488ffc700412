# Moldtex preset "branching veins" (continuous model): layton-intrinsic-slime.md Fig. 9a,
# a shallow sensor angle with agent turnover (mean lifetime 1 s, activation time 3 s).
# Agents see only what lies almost straight ahead, so they run along trails and branch
# off them at shallow angles; only the agents older than 3 s (about 5 %) lay pheromone,
# so the few long-lived paths stand out as thin veins. On Suzanne at 512², 60 000
# agents: veins everywhere after 3 s (std of u/U 1.0), sparser and sharper at 10 s
# (std 2.4, 65 % of the surface below 0.25 U).
# Look: Continuous model: thin, long branching veins, like lightning or leaf veins (shallow sensor angle, turnover).
import math
import bpy
obj = bpy.context.object
s = obj.moldtex
c = s.continuous
s.model = 'CONTINUOUS'
c.keep_u = False  # (set last: the U it keeps is this look's)
c.move_rate = 50.0
c.turn_rate = math.radians(360.0)
c.turn_frequency = 20.0
c.sensor_distance = 20.0
c.sensor_angle = math.radians(10.0)
c.deposit_rate = 1.0
c.diffusion_rate = 3.0
c.decay_rate = 1.5
c.mean_lifetime = 1.0
c.activation_time = 3.0
c.integrator = 'AUTO'
c.display_range = 3.0
s.time_step = 1.0 / 60.0
s.agent_count = 60000  # the continuous model's look does not depend on the resolution
c.keep_u = True
s.apply_ramp([
    (0.00, (0.005, 0.008, 0.025, 1.0)),  # night blue
    (0.12, (0.010, 0.040, 0.090, 1.0)),
    (0.40, (0.050, 0.350, 0.600, 1.0)),  # cyan glow
    (0.75, (0.550, 0.850, 1.000, 1.0)),
    (1.00, (0.950, 0.980, 1.000, 1.0)),  # white-hot core
], interpolation='LINEAR')
