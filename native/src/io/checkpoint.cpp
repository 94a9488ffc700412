#include "io/checkpoint.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "common/error.h"
#include "io/image_writer.h"

namespace moldtex {

namespace {

// Version 2: species (per-agent species, one pheromone plane per species, species
// parameters) and static fields. Version 3: food with hunger (per-agent hunger, food
// sources with their amounts left, the hunger parameters). Version 4: sensor_size
// appended to the parameters. Version 5: length_unit appended to the parameters.
constexpr char kMagic[8] = {'M', 'T', 'X', 'C', 'K', 'P', 'T', '5'};

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
  f(s.pheromone);
}

}  // namespace

void save_checkpoint(const std::string& path, const Checkpoint& c) {
  Writer w;
  w.raw(kMagic, sizeof(kMagic));
  w.value(c.config);
  w.value(c.params);
  w.value(c.surface_fingerprint);
  w.value(c.step_count);
  w.array(c.metrics);
  w.array(c.species);
  w.array(c.fields_rgba);
  w.array(c.food);
  for_each_array(c.state, [&](const auto& v) { w.array(v); });
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
  c.surface_fingerprint = r.value<uint64_t>();
  c.step_count = r.value<uint64_t>();
  r.array(c.metrics);
  r.array(c.species);
  r.array(c.fields_rgba);
  r.array(c.food);
  for_each_array(c.state, [&](auto& v) { r.array(v); });
  return c;
}

}  // namespace moldtex
