# Moldtex preset "reaction worms" (Gray-Scott): F 0.078, k 0.061 with the classic
# pixel-unit rates: short separate worms that split and spread slowly. Many seeds (256)
# because the worms spread slowly: on Suzanne at 128² (Pattern Scale 4) V > 0.1 on 37%
# of the area after 2500 s.
# Look: Gray-Scott: short separate worms on a plain ground.
import bpy
obj = bpy.context.object
s = obj.moldtex
r = s.reaction
s.model = 'GRAY_SCOTT'
r.feed = 0.078
r.kill = 0.061
r.diffusion_u = 0.2
r.diffusion_v = 0.1
r.time_step = 1.0
r.seed_count = 256
r.seed_radius = 5.0
r.display_range = 0.4
s.apply_ramp([
    (0.00, (0.050, 0.080, 0.120, 1.0)),  # deep blue ground
    (0.35, (0.060, 0.100, 0.150, 1.0)),
    (0.70, (0.300, 0.850, 0.800, 1.0)),  # cyan worms
    (1.00, (0.900, 1.000, 0.950, 1.0)),
], interpolation='EASE')
