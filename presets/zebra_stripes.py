# Moldtex preset "zebra stripes" (continuous model): layton-intrinsic-slime.md Fig. 9c,
# chemo-repulsion: a negative sensor angle turns agents away from pheromone (Jones'
# scheme), which sorts them into parallel bands, Turing-like stripes. The contrast is
# gentle (u/U between about 0.5 and 1.5), so the display range is 2 and the ramp turns
# from black to white around its middle. Slow decay (0.5/s): the stripes settle within
# about 6 s. On Suzanne at 512², 60 000 agents: stripes after 3 s, std of u/U 0.28 at
# 10 s.
# Look: Continuous model: black and white Turing-like stripes (chemo-repulsion: a negative sensor angle).
import math
import bpy
obj = bpy.context.object
s = obj.moldtex
c = s.continuous
s.model = 'CONTINUOUS'
c.keep_u = False  # (set last: the U it keeps is this look's)
c.move_rate = 40.0
c.turn_rate = math.radians(720.0)
c.turn_frequency = 20.0
c.sensor_distance = 14.0
c.sensor_angle = math.radians(-45.0)
c.deposit_rate = 1.0
c.diffusion_rate = 4.0
c.decay_rate = 0.5
c.mean_lifetime = 0.0
c.activation_time = 0.0
c.integrator = 'AUTO'
c.display_range = 2.0
s.time_step = 1.0 / 60.0
s.agent_count = 60000  # the continuous model's look does not depend on the resolution
c.keep_u = True
s.apply_ramp([
    (0.00, (0.010, 0.010, 0.010, 1.0)),  # black
    (0.44, (0.020, 0.018, 0.015, 1.0)),
    (0.56, (0.850, 0.820, 0.760, 1.0)),  # off-white
    (1.00, (0.950, 0.930, 0.880, 1.0)),
], interpolation='EASE')
