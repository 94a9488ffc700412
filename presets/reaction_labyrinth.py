# Moldtex preset "reaction labyrinth" (Gray-Scott): F 0.037, k 0.06 with the classic
# pixel-unit rates: stripes that branch and meander into a maze, like a brain coral or
# a fingerprint. On Suzanne at 128² (Pattern Scale 4) the maze covers the surface after
# about 2500 s (V > 0.1 on 64% of the area: the stripes and the gaps between them).
# Look: Gray-Scott: meandering stripes, a maze like a brain coral or a fingerprint.
import bpy
obj = bpy.context.object
s = obj.moldtex
r = s.reaction
s.model = 'GRAY_SCOTT'
r.feed = 0.037
r.kill = 0.06
r.diffusion_u = 0.2
r.diffusion_v = 0.1
r.time_step = 1.0
r.seed_count = 64
r.seed_radius = 5.0
r.display_range = 0.5
s.apply_ramp([
    (0.00, (0.900, 0.860, 0.780, 1.0)),  # bone
    (0.40, (0.850, 0.780, 0.680, 1.0)),
    (0.65, (0.450, 0.120, 0.100, 1.0)),  # coral red
    (1.00, (0.250, 0.050, 0.050, 1.0)),
], interpolation='EASE')
