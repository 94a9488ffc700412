#include "io/checkpoint.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "common/error.h"
#include "io/image_writer.h"

namespace moldtex {

namespace {

// Version 2: species (per-agent species, one pheromone plane per species, species
// parameters) and static fields. Version 3: food with hunger (per-agent hunger, food
// sources with their amounts left, the hunger parameters). Version 4: sensor_size
// appended to the parameters. Version 5: length_unit appended to the parameters.
// Version 6: the continuous model (config.model, its parameters, simulated time, the
// agents' clocks).
// Version 8: the Gray-Scott model's parameters, at the end of the file.
// Version 9: the config's domain fields (moldtex_sim_config grew), and the intrinsic
// domain's vertex values at the end.
constexpr char kMagic[8] = {'M', 'T', 'X', 'C', 'K', 'P', 'T', '9'};

struct Writer {
  std::vector<char> bytes;
  void raw(const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    bytes.insert(bytes.end(), c, c + n);
  }
  template <class T>
  void value(const T& v) { raw(&v, sizeof(T)); }
  template <class T>
  void array(const std::vector<T>& v) {
    value<uint64_t>(v.size());
    raw(v.data(), v.size() * sizeof(T));
  }
};

struct Reader {
  const std::vector<char>& bytes;
  const std::string& path;
  size_t at = 0;
  void raw(void* p, size_t n) {
    if (n > bytes.size() - at)
      fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is truncated or damaged");
    if (n == 0) return;  // an empty array's data() may be NULL: no memcpy(NULL, ..., 0)
    std::memcpy(p, bytes.data() + at, n);
    at += n;
  }
  template <class T>
  T value() {
    T v;
    raw(&v, sizeof(T));
    return v;
  }
  template <class T>
  void array(std::vector<T>& v) {
    uint64_t n = value<uint64_t>();
    if (n > (bytes.size() - at) / sizeof(T))
      fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is truncated or damaged");
    v.resize(n);
    raw(v.data(), n * sizeof(T));
  }
};

// The arrays of a state, in file order.
template <class State, class F>
void for_each_array(State& s, F&& f) {
  f(s.agents.triangle);
  f(s.agents.b1);
  f(s.agents.b2);
  f(s.agents.hx);
  f(s.agents.hy);
  f(s.agents.species);
  f(s.agents.hunger);
  f(s.agents.clock);
  f(s.agents.age);
  f(s.agents.exposure);
  f(s.agents.threshold);
  f(s.pheromone);
}

}  // namespace

namespace {

[[noreturn]] void damaged(const std::string& path, const std::string& what) {
  fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is damaged: " + what + ". Bake from the start");
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

}  // namespace

void validate_checkpoint_values(const Checkpoint& c, const std::string& path, uint32_t triangle_count,
                                uint32_t species_count) {
  const Agents& a = c.state.agents;
  for (size_t i = 0; i < a.size(); ++i) {
    const std::string agent = "agent " + std::to_string(i);
    if (a.triangle[i] >= triangle_count)
      damaged(path, agent + " stands on triangle " + std::to_string(a.triangle[i]) + " but the mesh has " +
                        std::to_string(triangle_count));
    const float b1 = a.b1[i], b2 = a.b2[i];
    // Barycentrics (1 - b1 - b2, b1, b2) on the triangle, up to rounding.
    if (!(b1 >= 0.f && b1 <= 1.f && b2 >= 0.f && b2 <= 1.f && b1 + b2 <= 1.f + kBaryTolerance))
      damaged(path, agent + " has barycentric weights (" + number(1.0 - b1 - b2) + ", " + number(b1) + ", " +
                        number(b2) + ") off its triangle (each must be in 0 .. 1, summing to 1)");
    const float hx = a.hx[i], hy = a.hy[i];
    const double length = std::sqrt(double(hx) * hx + double(hy) * hy);
    if (!(std::fabs(length - 1.0) <= kHeadingTolerance))
      damaged(path, agent + " has the heading (" + number(hx) + ", " + number(hy) +
                        "), not a unit vector");
    if (a.species[i] >= species_count)
      damaged(path, agent + " is of species " + std::to_string(a.species[i]) + " but the simulation has " +
                        std::to_string(species_count));
    if (!(a.hunger[i] >= 0.f && a.hunger[i] <= 1.f))
      damaged(path, agent + " has the hunger " + number(a.hunger[i]) + " (must be in 0 .. 1)");
    // The continuous model's clocks (a threshold may be FLT_MAX: no turnover).
    if (!(a.clock[i] >= 0.f && a.age[i] >= 0.f && a.exposure[i] >= 0.f && a.threshold[i] >= 0.f) ||
        !std::isfinite(a.clock[i]) || !std::isfinite(a.age[i]) || !std::isfinite(a.exposure[i]) ||
        !std::isfinite(a.threshold[i]))
      damaged(path, agent + " has a clock, age, exposure or threshold that is negative or not a number");
  }
  const bool continuous =
      c.config.model == MOLDTEX_MODEL_CONTINUOUS || c.config.model == MOLDTEX_MODEL_GRAY_SCOTT;
  const double max_pheromone = continuous ? std::numeric_limits<float>::max() : kMaxPheromone;
  const double max_coverage = continuous ? 1e30 : 1.0;
  for (size_t i = 0; i < c.state.cells.size(); ++i) {
    const float v = c.state.cells[i];
    if (!(v >= 0.f && v <= max_pheromone))
      damaged(path, "intrinsic vertex value " + std::to_string(i) + " is " + number(v));
  }
  for (size_t i = 0; i < c.state.pheromone.size(); ++i) {
    const float v = c.state.pheromone[i];
    if (!(v >= 0.f && v <= max_pheromone))
      damaged(path, "texel " + std::to_string(i) + " holds the pheromone " + number(v) +
                        (continuous ? " (must be a finite number >= 0)" : " (must be a number in 0 .. 1)"));
  }
  for (size_t r = 0; r < c.metrics.size(); ++r) {
    const MetricRow& m = c.metrics[r];
    const std::string row = "metrics row " + std::to_string(r);
    if (m.frame < 0 || m.frame > kMaxFrame || (r > 0 && m.frame <= c.metrics[r - 1].frame))
      damaged(path, row + " has the frame " + std::to_string(m.frame) +
                        " (frames must increase and lie in 0 .. " + std::to_string(kMaxFrame) + ")");
    if (m.step > c.step_count)
      damaged(path, row + " is at step " + std::to_string(m.step) + ", after the checkpoint's step " +
                        std::to_string(c.step_count));
    if (!(m.coverage >= 0.0 && m.coverage <= max_coverage) || !(m.presence >= 0.0 && m.presence <= 1.0))
      damaged(path, row + " has the coverage " + number(m.coverage) + " and presence " + number(m.presence) +
                        " (each must be in 0 .. 1)");
  }
}

void save_checkpoint(const std::string& path, const Checkpoint& c) {
  Writer w;
  w.raw(kMagic, sizeof(kMagic));
  w.value(c.config);
  w.value(c.params);
  w.value(c.continuous);
  w.value(c.time);
  w.value(c.surface_fingerprint);
  w.value(c.step_count);
  w.array(c.metrics);
  w.array(c.species);
  w.array(c.fields_rgba);
  w.array(c.food);
  w.array(c.bias);
  w.array(c.map_kinds);
  w.array(c.maps);
  for_each_array(c.state, [&](const auto& v) { w.array(v); });
  w.value(c.reaction);  // version 8: after the state, so the layout before it is version 7's
  w.array(c.state.cells);  // version 9
  write_file_atomically(path, w.bytes.data(), w.bytes.size());
}

Checkpoint load_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(MOLDTEX_ERROR_IO, "Could not open the checkpoint " + path);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Reader r{bytes, path};
  char magic[8];
  r.raw(magic, sizeof(magic));
  if (std::memcmp(magic, kMagic, sizeof(magic)) != 0)
    fail(MOLDTEX_ERROR_IO, path + " is not a Moldtex checkpoint of this version");
  Checkpoint c;
  c.config = r.value<moldtex_sim_config>();
  c.config.fields_rgba = nullptr;  // a pointer is meaningless in a file
  c.params = r.value<moldtex_sim_params>();
  c.continuous = r.value<moldtex_continuous_params>();
  c.time = r.value<double>();
  c.surface_fingerprint = r.value<uint64_t>();
  c.step_count = r.value<uint64_t>();
  r.array(c.metrics);
  r.array(c.species);
  r.array(c.fields_rgba);
  r.array(c.food);
  r.array(c.bias);
  r.array(c.map_kinds);
  r.array(c.maps);
  for_each_array(c.state, [&](auto& v) { r.array(v); });
  c.reaction = r.value<moldtex_reaction_params>();
  r.array(c.state.cells);
  return c;
}

}  // namespace moldtex
