#include "io/checkpoint.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <type_traits>

#include "common/error.h"
#include "io/image_writer.h"
#include "models/model.h"

namespace moldtex {

// File layout (docs/ARCHITECTURE.md, "Checkpoints"). Since format 10 a checkpoint is a
// list of tagged, versioned sections, so that every later version reads it:
//
//   "MTXCHKPT", uint32 format (the writer's), uint32 oldest format able to read it,
//   then sections: char tag[4], uint32 section version, uint32 flags, uint64 length,
//   `length` bytes; the list ends with the tag "END ".
//
// A reader skips a section it does not know unless its flags say it must be understood
// (kMustUnderstand), and then refuses the file naming the section. A parameter struct is
// a record: its uint32 size, then its bytes; a reader takes what it knows of it over the
// struct's defaults (the C API's struct_size rule: structs only grow at their end). The
// agents are named arrays, so an attribute added later is an array more. Format 9 (the
// raw layout before, magic "MTXCKPT9") is still read by read_format9 below.

namespace {

// Version 2: species (per-agent species, one pheromone plane per species, species
// parameters) and static fields. Version 3: food with hunger. Version 4: sensor_size
// appended to the parameters. Version 5: length_unit appended to the parameters.
// Version 6: the continuous model (config.model, its parameters, simulated time, the
// agents' clocks). Version 8: the Gray-Scott model's parameters, at the end of the file.
// Version 9: the config's domain fields, and the intrinsic domain's vertex values at the
// end. Version 10: sections.
constexpr char kLegacyMagic[7] = {'M', 'T', 'X', 'C', 'K', 'P', 'T'};  // + the version digit
constexpr char kMagic[8] = {'M', 'T', 'X', 'C', 'H', 'K', 'P', 'T'};
constexpr uint32_t kFormat = 10;         // what this version writes
constexpr uint32_t kOldestReader = 10;   // the oldest format whose reader can read it
constexpr uint32_t kOldestReadable = 9;  // the oldest format this version reads
constexpr uint32_t kMustUnderstand = 1;  // section flag: a reader that does not know it refuses the file

// The parameter structs' sizes in format 9 (the structs then; they only grow at their end).
constexpr uint32_t kV9ConfigBytes = 96, kV9ParamsBytes = 60, kV9ContinuousBytes = 68, kV9ReactionBytes = 32,
                   kV9SpeciesBytes = 40, kV9FoodBytes = 20;
static_assert(sizeof(moldtex_sim_config) >= kV9ConfigBytes && sizeof(moldtex_sim_params) >= kV9ParamsBytes &&
                  sizeof(moldtex_continuous_params) >= kV9ContinuousBytes &&
                  sizeof(moldtex_reaction_params) >= kV9ReactionBytes &&
                  sizeof(moldtex_species_params) >= kV9SpeciesBytes && sizeof(moldtex_food_source) >= kV9FoodBytes,
              "a public struct shrank: checkpoints of format 9 would no longer load");

// A struct's defaults, for the records that carry only its first bytes.
template <class T>
T defaults() {
  T v{};
  if constexpr (std::is_same_v<T, moldtex_sim_config>) moldtex_sim_config_init(&v);
  if constexpr (std::is_same_v<T, moldtex_sim_params>) moldtex_sim_params_init(&v);
  if constexpr (std::is_same_v<T, moldtex_continuous_params>) moldtex_continuous_params_init(&v);
  if constexpr (std::is_same_v<T, moldtex_reaction_params>) moldtex_reaction_params_init(&v);
  if constexpr (std::is_same_v<T, moldtex_species_params>) moldtex_species_params_init(&v, 0);
  return v;
}

template <class T>
constexpr bool has_struct_size() {
  return !std::is_same_v<T, moldtex_food_source>;
}

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
  // A parameter struct: its size, then its bytes.
  template <class T>
  void record(const T& v) {
    value<uint32_t>(sizeof(T));
    value(v);
  }
  // A section: `fill` writes its payload; the length is filled in after.
  template <class F>
  void section(const char (&tag)[5], uint32_t version, uint32_t flags, F&& fill) {
    raw(tag, 4);
    value(version);
    value(flags);
    const size_t length_at = bytes.size();
    value<uint64_t>(0);
    const size_t begin = bytes.size();
    fill();
    const uint64_t length = bytes.size() - begin;
    std::memcpy(bytes.data() + length_at, &length, sizeof(length));
  }
};

struct Reader {
  const std::vector<char>& bytes;
  const std::string& path;
  size_t at = 0;
  size_t end = bytes.size();  // of the section being read
  [[noreturn]] void truncated() const {
    fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is truncated or damaged");
  }
  void raw(void* p, size_t n) {
    if (n > end - at) truncated();
    if (n == 0) return;  // an empty array's data() may be NULL: no memcpy(NULL, ..., 0)
    std::memcpy(p, bytes.data() + at, n);
    at += n;
  }
  void skip(size_t n) {
    if (n > end - at) truncated();
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
    if (n > (end - at) / sizeof(T)) truncated();
    v.resize(n);
    raw(v.data(), n * sizeof(T));
  }
  // `size` bytes of a T over its defaults (more than sizeof(T): a later version's tail,
  // skipped).
  template <class T>
  T struct_of(size_t size) {
    T v = defaults<T>();
    const size_t known = std::min(size, sizeof(T));
    raw(&v, known);
    skip(size - known);
    if constexpr (has_struct_size<T>()) v.struct_size = sizeof(T);
    return v;
  }
  template <class T>
  T record() { return struct_of<T>(value<uint32_t>()); }
  // `n` records; their count bounded by the bytes left.
  template <class T>
  void records(std::vector<T>& v, uint64_t n) {
    if (n > (end - at) / 4) truncated();
    v.clear();
    for (uint64_t i = 0; i < n; ++i) v.push_back(record<T>());
  }
};

// The agents' arrays by name (format 10's AGNT section), in format 9's file order; the
// pheromone follows them there.
template <class State, class F>
void for_each_agent_array(State& s, F&& f) {
  f("triangle", s.agents.triangle);
  f("b1", s.agents.b1);
  f("b2", s.agents.b2);
  f("hx", s.agents.hx);
  f("hy", s.agents.hy);
  f("species", s.agents.species);
  f("hunger", s.agents.hunger);
  f("clock", s.agents.clock);
  f("age", s.agents.age);
  f("exposure", s.agents.exposure);
  f("threshold", s.agents.threshold);
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
  // The model's bound (MoMaS: kMaxPheromone; concentrations: any finite value).
  const Model& model = model_of(c.config.model);
  const double max_pheromone = model.max_plane_value();
  const bool continuous = max_pheromone > 1.0;
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
  w.value(kFormat);
  w.value(kOldestReader);
  const uint32_t must = kMustUnderstand;
  w.section("HEAD", 1, must, [&] {
    w.value(c.surface_fingerprint);
    w.value(c.step_count);
    w.value(c.time);
  });
  moldtex_sim_config config = c.config;
  config.fields_rgba = nullptr;  // a pointer is meaningless in a file
  w.section("CONF", 1, must, [&] { w.record(config); });
  w.section("PARM", 1, must, [&] { w.record(c.params); });
  w.section("SPEC", 1, must, [&] {
    w.value<uint64_t>(c.species.size());
    for (const moldtex_species_params& sp : c.species) w.record(sp);
  });
  w.section("CONT", 1, must, [&] { w.record(c.continuous); });
  w.section("GRSC", 1, must, [&] { w.record(c.reaction); });
  w.section("METR", 1, must, [&] {
    w.value<uint64_t>(c.metrics.size());
    for (const MetricRow& m : c.metrics) {
      w.value(m.frame);
      w.value<int32_t>(0);
      w.value(m.step);
      w.value(m.coverage);
      w.value(m.presence);
    }
  });
  w.section("FLDS", 1, must, [&] { w.array(c.fields_rgba); });
  w.section("FOOD", 1, must, [&] {
    w.value<uint64_t>(c.food.size());
    for (const moldtex_food_source& f : c.food) w.record(f);
  });
  w.section("BIAS", 1, must, [&] { w.array(c.bias); });
  w.section("MAPS", 1, must, [&] {
    const size_t per_map = c.map_kinds.empty() ? 0 : c.maps.size() / c.map_kinds.size();
    w.value<uint64_t>(c.map_kinds.size());
    for (size_t j = 0; j < c.map_kinds.size(); ++j) {
      w.value(c.map_kinds[j]);
      w.value<uint64_t>(per_map);
      w.raw(c.maps.data() + j * per_map, per_map * sizeof(float));
    }
  });
  w.section("AGNT", 1, must, [&] {
    w.value<uint64_t>(c.state.agents.size());
    w.value<uint32_t>(11);
    for_each_agent_array(c.state, [&](const char* name, const auto& v) {
      char tag[16] = {};  // the name, NUL-padded
      std::memcpy(tag, name, std::min(sizeof(tag), std::strlen(name)));
      w.raw(tag, sizeof(tag));
      w.value<uint32_t>(sizeof(v[0]));
      w.array(v);
    });
  });
  w.section("PHER", 1, must, [&] { w.array(c.state.pheromone); });
  w.section("CELL", 1, must, [&] { w.array(c.state.cells); });
  w.raw("END ", 4);
  w.value<uint32_t>(1);
  w.value<uint32_t>(0);
  w.value<uint64_t>(0);
  write_file_atomically(path, w.bytes.data(), w.bytes.size());
}

namespace {

// Format 9: raw structs and arrays in a fixed order.
Checkpoint read_format9(Reader& r) {
  Checkpoint c;
  c.config = r.struct_of<moldtex_sim_config>(kV9ConfigBytes);
  c.params = r.struct_of<moldtex_sim_params>(kV9ParamsBytes);
  c.continuous = r.struct_of<moldtex_continuous_params>(kV9ContinuousBytes);
  c.time = r.value<double>();
  c.surface_fingerprint = r.value<uint64_t>();
  c.step_count = r.value<uint64_t>();
  r.array(c.metrics);  // MetricRow's 32 bytes, unchanged
  auto records = [&](auto& v, uint32_t size) {
    const uint64_t n = r.value<uint64_t>();
    if (n > (r.end - r.at) / size) r.truncated();
    v.clear();
    for (uint64_t i = 0; i < n; ++i) v.push_back(r.struct_of<typename std::decay_t<decltype(v)>::value_type>(size));
  };
  records(c.species, kV9SpeciesBytes);
  r.array(c.fields_rgba);
  records(c.food, kV9FoodBytes);
  r.array(c.bias);
  r.array(c.map_kinds);
  r.array(c.maps);
  for_each_agent_array(c.state, [&](const char*, auto& v) { r.array(v); });
  r.array(c.state.pheromone);
  c.reaction = r.struct_of<moldtex_reaction_params>(kV9ReactionBytes);
  r.array(c.state.cells);
  return c;
}

// Format 10 and later: the sections after the header.
Checkpoint read_sections(Reader& r) {
  Checkpoint c;
  std::vector<std::string> seen;
  const auto need = [&](const char* tag) {
    if (std::find(seen.begin(), seen.end(), tag) == seen.end())
      fail(MOLDTEX_ERROR_IO, "The checkpoint " + r.path + " is damaged: it has no " + tag + " section");
  };
  for (;;) {
    char tag_bytes[4];
    r.raw(tag_bytes, 4);
    const std::string tag(tag_bytes, 4);
    const uint32_t version = r.value<uint32_t>(), flags = r.value<uint32_t>();
    const uint64_t length = r.value<uint64_t>();
    if (tag == "END ") break;
    if (length > r.bytes.size() - r.at) r.truncated();
    if (std::find(seen.begin(), seen.end(), tag) != seen.end())
      fail(MOLDTEX_ERROR_IO, "The checkpoint " + r.path + " is damaged: it has two " + tag + " sections");
    seen.push_back(tag);
    const size_t section_end = r.at + length;
    r.end = section_end;
    // Every section here is at its version 1; a later version of one must say whether an
    // older reader may skip it (its flags).
    const bool known = version == 1 && (tag == "HEAD" || tag == "CONF" || tag == "PARM" || tag == "SPEC" ||
                                         tag == "CONT" || tag == "GRSC" || tag == "METR" || tag == "FLDS" ||
                                         tag == "FOOD" || tag == "BIAS" || tag == "MAPS" || tag == "AGNT" ||
                                         tag == "PHER" || tag == "CELL");
    if (!known) {
      if (flags & kMustUnderstand)
        fail(MOLDTEX_ERROR_IO, "The checkpoint " + r.path + " holds a section this version of Moldtex does not know (" +
                                   tag + ", version " + std::to_string(version) +
                                   "): it was written by a newer Moldtex; update Moldtex, or bake from the start");
    } else if (tag == "HEAD") {
      c.surface_fingerprint = r.value<uint64_t>();
      c.step_count = r.value<uint64_t>();
      c.time = r.value<double>();
    } else if (tag == "CONF") {
      c.config = r.record<moldtex_sim_config>();
    } else if (tag == "PARM") {
      c.params = r.record<moldtex_sim_params>();
    } else if (tag == "SPEC") {
      r.records(c.species, r.value<uint64_t>());
    } else if (tag == "CONT") {
      c.continuous = r.record<moldtex_continuous_params>();
    } else if (tag == "GRSC") {
      c.reaction = r.record<moldtex_reaction_params>();
    } else if (tag == "METR") {
      const uint64_t n = r.value<uint64_t>();
      if (n > (r.end - r.at) / 32) r.truncated();
      c.metrics.resize(n);
      for (MetricRow& m : c.metrics) {
        m.frame = r.value<int32_t>();
        r.value<int32_t>();
        m.step = r.value<uint64_t>();
        m.coverage = r.value<double>();
        m.presence = r.value<double>();
      }
    } else if (tag == "FLDS") {
      r.array(c.fields_rgba);
    } else if (tag == "FOOD") {
      r.records(c.food, r.value<uint64_t>());
    } else if (tag == "BIAS") {
      r.array(c.bias);
    } else if (tag == "MAPS") {
      const uint64_t n = r.value<uint64_t>();
      if (n > MOLDTEX_MAP_COUNT)
        fail(MOLDTEX_ERROR_IO, "The checkpoint " + r.path + " is damaged: it holds " + std::to_string(n) + " maps");
      std::vector<float> values;
      for (uint64_t j = 0; j < n; ++j) {
        c.map_kinds.push_back(r.value<uint32_t>());
        r.array(values);
        c.maps.insert(c.maps.end(), values.begin(), values.end());
        if (c.maps.size() != values.size() * (j + 1))
          fail(MOLDTEX_ERROR_IO, "The checkpoint " + r.path + " is damaged: its maps differ in size");
      }
    } else if (tag == "AGNT") {
      const uint64_t count = r.value<uint64_t>();
      const uint32_t arrays = r.value<uint32_t>();
      std::vector<std::string> names;
      for (uint32_t a = 0; a < arrays; ++a) {
        char name_bytes[17] = {};
        r.raw(name_bytes, 16);
        const std::string name(name_bytes);
        const uint32_t element = r.value<uint32_t>();
        bool taken = false;
        for_each_agent_array(c.state, [&](const char* known_name, auto& v) {
          if (taken || name != known_name) return;
          if (element != sizeof(v[0]))
            fail(MOLDTEX_ERROR_IO, "The checkpoint " + r.path + " is damaged: the agents' " + name + " are of " +
                                       std::to_string(element) + " bytes each");
          r.array(v);
          taken = true;
        });
        if (!taken) {  // an attribute of a later version: skipped
          const uint64_t n = r.value<uint64_t>();
          if (element == 0 || n > (r.end - r.at) / element) r.truncated();
          r.skip(n * element);
        }
        names.push_back(name);
      }
      for_each_agent_array(c.state, [&](const char* known_name, auto& v) {
        if (std::find(names.begin(), names.end(), known_name) == names.end() || v.size() != count)
          fail(MOLDTEX_ERROR_IO, "The checkpoint " + r.path + " is damaged: the agents' " + known_name +
                                     " are missing or of another count");
      });
    } else if (tag == "PHER") {
      r.array(c.state.pheromone);
    } else if (tag == "CELL") {
      r.array(c.state.cells);
    }
    r.at = section_end;  // (a known section's later bytes, or an unknown one, skipped)
    r.end = r.bytes.size();
  }
  for (const char* tag : {"HEAD", "CONF", "PARM", "SPEC", "AGNT", "PHER"}) need(tag);
  if (c.config.model == MOLDTEX_MODEL_CONTINUOUS) need("CONT");
  if (c.config.model == MOLDTEX_MODEL_GRAY_SCOTT) need("GRSC");
  return c;
}

}  // namespace

Checkpoint load_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(MOLDTEX_ERROR_IO, "Could not open the checkpoint " + path);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Reader r{bytes, path};
  char magic[8];
  r.raw(magic, sizeof(magic));
  Checkpoint c;
  if (std::memcmp(magic, kMagic, sizeof(magic)) == 0) {
    const uint32_t format = r.value<uint32_t>(), oldest_reader = r.value<uint32_t>();
    if (oldest_reader > kFormat)
      fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is of format " + std::to_string(format) +
                                 ", which needs a Moldtex that reads format " + std::to_string(oldest_reader) +
                                 " or later (this one reads " + std::to_string(kOldestReadable) + " to " +
                                 std::to_string(kFormat) + "): update Moldtex, or bake from the start");
    c = read_sections(r);
  } else if (std::memcmp(magic, kLegacyMagic, sizeof(kLegacyMagic)) == 0 && magic[7] >= '1' && magic[7] <= '9') {
    const int format = magic[7] - '0';
    if (format < int(kOldestReadable))
      fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is of format " + std::to_string(format) +
                                 ", from a Moldtex older than this one reads (formats " +
                                 std::to_string(kOldestReadable) + " to " + std::to_string(kFormat) +
                                 "): bake from the start");
    c = read_format9(r);
  } else {
    fail(MOLDTEX_ERROR_IO, path + " is not a Moldtex checkpoint");
  }
  c.config.fields_rgba = nullptr;  // a pointer is meaningless in a file
  return c;
}

}  // namespace moldtex
