// Spatial queries on a surface through Embree 3: nearest ray hit and closest point.
// The BVH is built on the first query (thread-safe) and lives as long as this object;
// the C API keeps one per surface handle. Triangles the surface marks as degenerate
// (zero 3D or UV area) are left out, so every answer is a point agents and brushes can
// use. Embree failures become moldtex::Error (never a crash).
#pragma once
#include <memory>
#include <mutex>

#include "moldtex.h"
#include "surface/surface.h"

namespace moldtex {

struct RayHitResult {
  bool hit = false;
  uint32_t triangle = 0;
  float bary[3] = {0, 0, 0};
  float distance = 0;  // ray parameter s
};

struct ClosestPointResult {
  uint32_t triangle = 0;
  float bary[3] = {0, 0, 0};
  double distance = 0;
};

// Throw INVALID_ARGUMENT (with a message naming the value) unless the query is one
// Embree can take: every coordinate finite and within +-1e18 (Embree asserts beyond
// ~1.8e18), a direction of length >= 1e-18 (shorter ones always miss), max_distance >= 0
// or +infinity. ray_cast and closest_point call them first.
void validate_ray(const float origin[3], const float direction[3], float max_distance);
void validate_query_point(const float position[3]);

class SpatialIndex {
 public:
  explicit SpatialIndex(std::shared_ptr<const Surface> surface);
  ~SpatialIndex();
  SpatialIndex(const SpatialIndex&) = delete;
  SpatialIndex& operator=(const SpatialIndex&) = delete;

  // origin + s * direction, 0 <= s <= max_distance (validated with validate_ray).
  RayHitResult ray_cast(const float origin[3], const float direction[3], float max_distance) const;
  // Exact nearest point (distance computed in double on each candidate triangle).
  ClosestPointResult closest_point(const float position[3]) const;

 private:
  struct Scene;
  const Scene& scene() const;

  std::shared_ptr<const Surface> surface_;
  mutable std::once_flag built_;
  mutable std::unique_ptr<Scene> scene_;
};

}  // namespace moldtex
