// The geodesic disk of a brush: straightest paths (shared/walk.h) from the centre along
// many rays, sampled densely enough that every texel the disk covers gets a sample.
//
// Spacing: 0.5 of the narrowest texel of the triangles met (the smallest 3D width of a
// texel's image) along a ray and between rays at the rim, so every texel's inscribed
// circle (radius >= width / 2) holds a sample on flat ground. The narrowest texel is
// found by a coarse pilot pass and refined if the dense pass meets narrower ones. Rays
// are nested (ray i = odd * 2^k is sampled only where the rays that are multiples of
// 2^(k+1) lie farther apart than the rim spacing), so a dab costs about 1.3 pi
// (r / step)^2 samples (12 ms for a radius of 96 texels, 105 ms for 384). The step is
// at least r / 1024: a dab with a radius above 512 texel widths is sampled more
// coarsely and may miss texels. r is the walked radius (disk_reach): at most about twice
// the mesh's geodesic extent, whatever the brush radius. On slivers far narrower than a
// step, where a step would cross 32 edges or more, a ray ends there, and a dab walks at
// most 2^24 edge crossings in all (sane dabs cross a few per sample).
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "moldtex.h"
#include "surface/surface.h"

namespace moldtex {

// Smallest 3D width of the image of one texel of a width x height texture on triangle t.
double texel_width(const Surface& s, uint32_t t, uint32_t width, uint32_t height);

class DiskVisitor {
 public:
  virtual ~DiskVisitor() = default;
  // Called before each (re)sampling pass; `step` is the spacing along the rays.
  virtual void begin(float step) = 0;
  // A point of the disk: a sample (is_sample) or an edge crossing / bounce between two
  // samples, at path length `distance` <= radius from the centre along ray `ray`. The
  // walker's heading is the ray's direction there (in the frame of w.triangle).
  virtual void visit(uint32_t ray, const Walker& w, float distance, bool is_sample) = 0;
};

// How far a dab of `radius` around `center` walks: `radius` itself, unless the disk
// holds all the surface its centre can reach (its connected part), in which case walking
// further only wraps around it again: then twice an upper bound of the geodesic distance
// from the centre to any point of that part (a shortest path over the triangles' adjacency,
// through edge midpoints, plus the farthest corner; twice, as straightest paths bounce
// instead of bending round corners). So the work of a dab, and of placing its agents, is
// bounded by the size of the mesh whatever the radius (issue 14: radius 1e4 on a 2 x 2
// plane took seconds). The cheap test first: a radius up to the largest 3D distance from
// the centre to a vertex is returned as it is, so such dabs are unchanged bit for bit.
float disk_reach(const Surface& s, const moldtex_surface_point& center, float radius);

// 1 for every triangle a walker starting on `triangle` can reach (across the adjacency).
std::vector<uint8_t> reachable_triangles(const Surface& s, uint32_t triangle);

// Samples the disk (centre validated: in range, not degenerate). `width` x `height` is
// the texture whose texels must all be reached. Paths are walked to
// disk_reach(s, center, radius) <= radius.
void sample_disk(const Surface& s, const moldtex_surface_point& center, float radius,
                 uint32_t width, uint32_t height, DiskVisitor& visitor);

// Distance from the centre of a disk to any point of the triangles it covers: each visit
// records the centre unfolded into the triangle's frame (point - distance * heading); a
// point's distance is the smallest to those unfolded centres. Exact on flat regions;
// elsewhere the length of a straight line in one of the rays' unfoldings.
class DiskDistance final : public DiskVisitor {
 public:
  explicit DiskDistance(const Surface& s) : surface_(s) {}
  void begin(float step) override;
  void visit(uint32_t ray, const Walker& w, float distance, bool is_sample) override;
  // +infinity for points in triangles the disk does not reach.
  float distance(uint32_t triangle, const float bary[3]) const;

 private:
  const Surface& surface_;
  float tolerance_ = 0;
  std::unordered_map<uint32_t, std::vector<Vec2>> centres_;
  std::vector<uint8_t> reached_;          // per triangle: has centres (no hash lookup for
                                          // the many points of a mesh the disk misses)
  uint32_t last_triangle_ = UINT32_MAX;   // consecutive visits mostly share a triangle
  std::vector<Vec2>* last_list_ = nullptr;  // (unordered_map values never move)
};

}  // namespace moldtex
