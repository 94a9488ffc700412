#include "brush/brush.h"

#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <unordered_map>

#include "brush/geodesic_disk.h"
#include "common/error.h"
#include "common/rng.h"
#include "shared/momas.h"

namespace moldtex {

namespace {

void require(bool ok, const std::string& message) {
  if (!ok) fail(MOLDTEX_ERROR_INVALID_ARGUMENT, message);
}

// Smallest path length from the centre per texel reached by a sample, kept in 32 x 32
// texel tiles (a dab touches few tiles, and consecutive samples mostly hit the same one).
class TexelDistances final : public DiskVisitor {
 public:
  static constexpr uint32_t kTile = 32;
  TexelDistances(const Surface& s, uint32_t width, uint32_t height)
      : surface_(s), width_(width), height_(height), tiles_x_((width + kTile - 1) / kTile) {}
  void begin(float) override {
    index_.clear();
    tiles_.clear();
    keys_.clear();
    last_ray_ = UINT32_MAX;
    last_key_ = UINT32_MAX;
  }
  void visit(uint32_t ray, const Walker& w, float distance, bool is_sample) override {
    if (!is_sample) return;
    float uv[2];
    surface_.evaluate(w.triangle, w.bary, nullptr, uv);
    const uint32_t texel = mtx_texel_of_uv(uv[0], uv[1], width_, height_);
    // Along one ray distances only grow: a texel just visited keeps its smaller one.
    if (ray == last_ray_ && texel == last_texel_) return;
    last_ray_ = ray;
    last_texel_ = texel;
    const uint32_t x = texel % width_, y = texel / width_;
    const uint32_t key = (y / kTile) * tiles_x_ + x / kTile;
    if (key != last_key_) {
      auto [it, inserted] = index_.try_emplace(key, static_cast<uint32_t>(tiles_.size()));
      if (inserted) {
        tiles_.emplace_back();
        tiles_.back().fill(kUnset);
        keys_.push_back(key);
      }
      last_key_ = key;
      last_tile_ = it->second;
    }
    float& best = tiles_[last_tile_][(y % kTile) * kTile + x % kTile];
    best = std::min(best, distance);
  }
  // Calls f(texel, distance) for every texel reached.
  template <class F>
  void for_each(F&& f) const {
    for (size_t t = 0; t < tiles_.size(); ++t) {
      const uint32_t x0 = (keys_[t] % tiles_x_) * kTile, y0 = (keys_[t] / tiles_x_) * kTile;
      for (uint32_t i = 0; i < kTile * kTile; ++i)
        if (tiles_[t][i] != kUnset) f((y0 + i / kTile) * width_ + x0 + i % kTile, tiles_[t][i]);
    }
  }

 private:
  static constexpr float kUnset = std::numeric_limits<float>::infinity();
  const Surface& surface_;
  uint32_t width_, height_, tiles_x_;
  uint32_t last_ray_ = UINT32_MAX, last_texel_ = 0, last_key_ = UINT32_MAX, last_tile_ = 0;
  std::unordered_map<uint32_t, uint32_t> index_;  // tile key -> tiles_ index
  std::vector<std::array<float, kTile * kTile>> tiles_;
  std::vector<uint32_t> keys_;
};

}  // namespace

void validate_brush(const Surface& s, const moldtex_brush& b) {
  // Below 1e-30 the sampling step (radius / 65536 at most) would underflow to 0.
  if (!(std::isfinite(b.radius) && b.radius >= 1e-30f && b.radius < 1e30f)) {
    std::ostringstream m;
    m << "The brush radius must be a number between 1e-30 and 1e30 (mesh units, measured on "
         "the surface), got "
      << b.radius;
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
  }
  require(std::isfinite(b.strength) && b.strength >= 0.f && b.strength <= 1.f,
          "The brush strength must be between 0 and 1");
  require(std::isfinite(b.falloff) && b.falloff >= 0.f && b.falloff <= 1.f,
          "The brush falloff must be between 0 and 1");
  require(b.mode <= MOLDTEX_BRUSH_ERASE, "Unknown brush mode: use 0 (paint) or 1 (erase)");
  require(std::isfinite(b.value), "The brush value must be a finite number");
  const moldtex_surface_point& p = b.center;
  require(p.triangle < s.triangle_count(), "The brush centre's triangle index is out of range");
  require(!s.degenerate[p.triangle], "The brush centre lies on a zero-area triangle");
  float sum = 0;
  for (float x : p.bary) {
    require(std::isfinite(x) && x >= -1e-4f,
            "The brush centre's barycentric weights must be finite and non-negative");
    sum += x;
  }
  require(std::fabs(sum - 1.f) < 1e-3f, "The brush centre's barycentric weights must sum to 1");
}

float brush_weight(float x, float falloff) {
  if (!(x <= 1.f)) return 0.f;
  const float inner = 1.f - falloff;
  if (x <= inner) return 1.f;
  const float t = (x - inner) / falloff;  // falloff > 0 here
  return 1.f - t * t * (3.f - 2.f * t);
}

uint32_t paint_dab(const Surface& s, uint32_t width, uint32_t height, float* rgba,
                   const moldtex_brush& brush) {
  TexelDistances texels(s, width, height);
  sample_disk(s, brush.center, brush.radius, width, height, texels);
  const float target = brush.mode == MOLDTEX_BRUSH_ERASE ? 0.f : brush.value;
  uint32_t changed = 0;
  texels.for_each([&](uint32_t texel, float d) {
    const float w = brush.strength * brush_weight(d / brush.radius, brush.falloff);
    float& v = rgba[4 * static_cast<size_t>(texel) + brush.channel];
    const float next = v + (target - v) * w;
    if (next != v) {
      v = next;
      ++changed;
    }
  });
  return changed;
}

Agents place_disk_agents(const Surface& s, const moldtex_brush& brush, uint32_t count,
                         uint64_t seed, uint16_t batch, uint64_t first_index, ThreadPool& pool) {
  Agents a;
  a.resize(count);
  const float two_pi = 2.f * std::numbers::pi_v<float>;
  // A disk that holds the whole reachable surface is walked no further than it needs.
  const float reach = count > 0 ? disk_reach(s, brush.center, brush.radius) : brush.radius;
  pool.parallel_for(count, 256, [&](size_t begin, size_t end) {
    for (size_t j = begin; j < end; ++j) {
      CounterRng rng(seed, MTX_RNG_BRUSH, (static_cast<uint64_t>(batch) << 40) ^ (first_index + j), 0);
      const float angle = rng.next_float() * two_pi;
      const float length = reach * std::sqrt(rng.next_float());
      const float heading = rng.next_float() * two_pi;
      Walker w{brush.center.triangle, {brush.center.bary[0], brush.center.bary[1], brush.center.bary[2]},
               {std::cos(angle), std::sin(angle)}};
      mtx_clamp_bary(w.bary);
      // In 16 legs, so that no single walk meets the crossing cap on a fine mesh.
      for (int leg = 0; leg < 16; ++leg)
        mtx_walk(s.frames.data(), s.adjacency.data(), &w, length / 16.f, nullptr, 0);
      w.heading = {std::cos(heading), std::sin(heading)};
      a.store(j, w);
      a.species[j] = static_cast<uint8_t>(brush.channel);
      a.hunger[j] = 0.f;
      a.batch[j] = batch;
    }
  });
  return a;
}

std::vector<uint8_t> erase_mask(const Surface& s, const moldtex_brush& brush, const Agents& agents,
                                uint32_t width, uint32_t height, uint64_t seed, uint16_t batch,
                                uint64_t dab) {
  std::vector<uint8_t> out(agents.size(), 0);
  auto draw = [&](size_t i, float p) {
    if (p >= 1.f) {
      out[i] = 1;
    } else if (p > 0.f) {
      CounterRng rng(seed, MTX_RNG_ERASE, (static_cast<uint64_t>(batch) << 40) ^ dab, i);
      out[i] = rng.next_float() < p;
    }
  };
  const float reach = disk_reach(s, brush.center, brush.radius);
  if (reach < brush.radius && brush_weight(reach / brush.radius, brush.falloff) >= 1.f) {
    // The disk holds every point its centre can reach, all at d <= reach, so at full
    // weight: no need to sample it, only to know which triangles are reachable.
    const std::vector<uint8_t> reached = reachable_triangles(s, brush.center.triangle);
    for (size_t i = 0; i < agents.size(); ++i)
      if (reached[agents.triangle[i]]) draw(i, brush.strength);
    return out;
  }
  DiskDistance disk(s);
  sample_disk(s, brush.center, brush.radius, width, height, disk);
  for (size_t i = 0; i < agents.size(); ++i) {
    const Walker w = agents.load(i);
    const float d = disk.distance(w.triangle, w.bary);
    if (!(d <= brush.radius)) continue;
    const float p = brush.strength * brush_weight(d / brush.radius, brush.falloff);
    draw(i, p);
  }
  return out;
}

}  // namespace moldtex
