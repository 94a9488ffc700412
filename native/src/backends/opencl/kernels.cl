/* kernels.cl — the OpenCL program. The host prepends shared/portable.h, constants.h,
 * rng.h, walk.h, momas.h and field.h (the same sources the CPU backend compiles as
 * C++), so these kernels only unpack buffers and call the shared functions. */

__kernel void momas_agents(__global const mtx_frame* frames, __global const uint* adjacency,
                           __global const float* corner_uvs, __global const uchar* classes,
                           __global const float* pheromone, __global uchar* marks,
                           __global uint* triangle, __global float* b1, __global float* b2,
                           __global float* hx, __global float* hy,
                           const mtx_momas_constants k, const uint count) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  mtx_surface_tables s;
  s.frames = frames;
  s.adjacency = adjacency;
  s.corner_uvs = corner_uvs;
  s.classes = classes;
  mtx_walker w;
  w.triangle = triangle[i];
  w.bary[1] = b1[i];
  w.bary[2] = b2[i];
  w.bary[0] = 1.0f - w.bary[1] - w.bary[2];
  w.heading.x = hx[i];
  w.heading.y = hy[i];
  mtx_momas_agent_step(s, pheromone, marks, &w, (ulong)i, &k);
  triangle[i] = w.triangle;
  b1[i] = w.bary[1];
  b2[i] = w.bary[2];
  hx[i] = w.heading.x;
  hy[i] = w.heading.y;
}

__kernel void apply_deposits(__global float* pheromone, __global uchar* marks,
                             const float deposit, const uint count) {
  const uint i = get_global_id(0);
  if (i >= count || !marks[i]) return;
  pheromone[i] = fmax(pheromone[i], deposit);
  marks[i] = 0;
}

/* Gutter texels copy island texels; the two sets are disjoint, so no write races. */
__kernel void fill_gutter(__global float* pheromone, __global const uint* gutter_texel,
                          __global const uint* gutter_source, const uint count) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  pheromone[gutter_texel[i]] = pheromone[gutter_source[i]];
}

__kernel void diffuse_evaporate(__global const float* in, __global float* out,
                                __global const uchar* classes, const int width,
                                const int height, const float mix, const float evaporation) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const uint i = (uint)y * (uint)width + (uint)x;
  out[i] = classes[i] == MTX_TEXEL_INSIDE
               ? mtx_diffuse_evaporate_texel(in, classes, x, y, width, height, mix, evaporation)
               : 0.0f;
}
