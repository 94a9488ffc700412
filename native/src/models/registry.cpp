// The models a simulation can run, by moldtex_model: the one list a new model joins.
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "models/model.h"

namespace moldtex {

// Defined in each model's folder.
const Model& momas_model();
const Model& continuous_model();
const Model& gray_scott_model();

namespace {

std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}

// The built-in models, then any registered (register_model).
std::vector<const Model*>& registered() {
  static std::vector<const Model*> models{&momas_model(), &continuous_model(), &gray_scott_model()};
  return models;
}

const Model* const* all_models(size_t* count) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  *count = registered().size();
  return registered().data();
}

}  // namespace

void register_model(const Model& model) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  for (const Model* m : registered())
    if (m->id() == model.id())
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "A model with the id " + std::to_string(model.id()) + " is registered");
  registered().push_back(&model);
}

const Model* find_model(uint32_t id) {
  size_t n = 0;
  const Model* const* models = all_models(&n);
  for (size_t i = 0; i < n; ++i)
    if (models[i]->id() == id) return models[i];
  return nullptr;
}

const Model& model_of(uint32_t id) {
  if (const Model* m = find_model(id)) return *m;
  size_t n = 0;
  const Model* const* models = all_models(&n);
  std::ostringstream message;
  message << "Unknown model: use";
  for (size_t i = 0; i < n; ++i)
    message << (i == 0 ? " " : i + 1 == n ? " or " : ", ") << models[i]->id() << " (" << models[i]->name_in_text()
            << ")";
  fail(MOLDTEX_ERROR_INVALID_ARGUMENT, message.str());
}

std::string models_on(uint32_t domain) {
  return models_that([domain](const Model& m) { return m.runs_on(domain); });
}

std::string models_that(const std::function<bool(const Model&)>& test) {
  size_t n = 0;
  const Model* const* models = all_models(&n);
  std::vector<const Model*> on;
  for (size_t i = 0; i < n; ++i)
    if (test(*models[i])) on.push_back(models[i]);
  std::string text;
  for (size_t i = 0; i < on.size(); ++i)
    text += std::string(i == 0 ? "" : i + 1 == on.size() ? " and " : ", ") + on[i]->name_in_text();
  return text;
}

}  // namespace moldtex
