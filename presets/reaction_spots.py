# Moldtex preset "reaction spots" (Gray-Scott): F 0.03, k 0.062 with the classic
# pixel-unit rates (D_u 0.2, D_v 0.1 pattern units² per second): the seeds grow into a
# front that leaves round spots of V behind, evenly spaced, until the surface is full.
# On Suzanne at 128² (Pattern Scale 4, the same look): V > 0.1 on 36% of the area
# after 2500 s, the spots still spreading.
# Look: Gray-Scott: evenly spaced spots, like a leopard's or a cheetah's coat.
import bpy
obj = bpy.context.object
s = obj.moldtex
r = s.reaction
s.model = 'GRAY_SCOTT'
r.feed = 0.03
r.kill = 0.062
r.diffusion_u = 0.2
r.diffusion_v = 0.1
r.time_step = 1.0
r.seed_count = 64
r.seed_radius = 5.0
r.display_range = 0.45
s.apply_ramp([
    (0.00, (0.800, 0.560, 0.250, 1.0)),  # tawny
    (0.45, (0.700, 0.450, 0.180, 1.0)),
    (0.60, (0.060, 0.040, 0.025, 1.0)),  # near-black spots
    (1.00, (0.020, 0.015, 0.010, 1.0)),
], interpolation='EASE')
