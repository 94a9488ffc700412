#include "bake/bake.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "common/error.h"
#include "io/image_writer.h"

namespace moldtex {

BakeOptions validate_bake(const moldtex_bake_desc& d) {
  BakeOptions o;
  if (!d.directory || !*d.directory)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The bake needs an output folder");
  std::error_code ec;
  if (!std::filesystem::is_directory(d.directory, ec))
    fail(MOLDTEX_ERROR_IO, std::string("The output folder ") + d.directory + " does not exist");
  o.directory = d.directory;
  o.prefix = d.file_prefix ? d.file_prefix : "moldtex_";
  if (o.prefix.find('/') != std::string::npos)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The file prefix must be a plain name without '/'");
  if (o.prefix.size() > 200)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The file prefix is " + std::to_string(o.prefix.size()) +
             " characters long: use at most 200 (file names have a length limit)");
  if (d.first_frame < 0 || d.last_frame < d.first_frame || d.last_frame > 999999)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The frame range must satisfy 0 <= first <= last <= 999999");
  if (d.steps_per_frame < 1 || d.steps_per_frame > 100000)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Steps per frame must be between 1 and 100000");
  if (d.format > MOLDTEX_IMAGE_PNG16) fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown image format");
  o.first_frame = d.first_frame;
  o.last_frame = d.last_frame;
  o.steps_per_frame = d.steps_per_frame;
  o.format = static_cast<moldtex_image_format>(d.format);
  o.write_checkpoints = d.write_checkpoints != 0;
  o.resume = d.resume != 0;
  return o;
}

Bake::Bake(std::shared_ptr<Simulation> sim, BakeOptions options)
    : sim_(std::move(sim)), options_(std::move(options)) {
  progress_.struct_size = sizeof(progress_);
  progress_.state = MOLDTEX_BAKE_RUNNING;
  progress_.first_frame = options_.first_frame;
  progress_.last_frame = options_.last_frame;
  progress_.last_frame_written = options_.first_frame - 1;
  sim_->busy = true;
  worker_ = std::thread([this] { run(); });
}

Bake::~Bake() {
  cancel();
  if (worker_.joinable()) worker_.join();
}

moldtex_status Bake::wait() {
  if (worker_.joinable()) worker_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  return outcome_;
}

moldtex_bake_progress Bake::progress() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return progress_;
}

std::string Bake::frame_path(int32_t frame) const {
  char number[16];
  std::snprintf(number, sizeof(number), "%04d", frame);
  const bool png = options_.format == MOLDTEX_IMAGE_PNG8 || options_.format == MOLDTEX_IMAGE_PNG16;
  return options_.directory + "/" + options_.prefix + number + (png ? ".png" : ".exr");
}

void Bake::write_metrics_csv(const std::vector<MetricRow>& rows) const {
  std::ostringstream csv;
  csv.precision(9);
  csv << "frame,step,coverage,presence\n";
  for (const MetricRow& r : rows) csv << r.frame << ',' << r.step << ',' << r.coverage << ',' << r.presence << '\n';
  const std::string text = csv.str();
  write_file_atomically(metrics_path(), text.data(), text.size());
}

void Bake::bake_frames() {
  Simulation& sim = *sim_;
  // Leftovers of a killed run are never frames; clear them.
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(options_.directory, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(options_.prefix, 0) == 0 && name.size() > 8 &&
        name.compare(name.size() - 8, 8, ".partial") == 0)
      std::filesystem::remove(entry.path(), ec);
  }
  std::vector<MetricRow> rows;
  int32_t next = options_.first_frame;
  if (options_.resume && std::filesystem::exists(checkpoint_path())) {
    rows = sim.load_checkpoint(checkpoint_path());  // frames validated: 0 .. 999999
    // Keep the rows of this bake's range that the checkpoint vouches for.
    std::erase_if(rows, [&](const MetricRow& r) { return r.frame < options_.first_frame; });
    if (!rows.empty()) next = rows.back().frame + 1;
    const uint64_t expected =
        static_cast<uint64_t>(int64_t{next} - options_.first_frame) * options_.steps_per_frame;
    if (sim.step_count() != expected)
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
           "The checkpoint was made with another frame range or steps per frame: bake from the start");
    // The CSV is renamed into place after the checkpoint: a run killed in between left
    // it a row short. The checkpoint's rows are the truth; write them now (also when
    // no frame is left to bake).
    write_metrics_csv(rows);
  } else {
    sim.reset();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    progress_.frames_done = static_cast<uint32_t>(next - options_.first_frame);
    progress_.last_frame_written = next - 1;
    progress_.step_count = sim.step_count();
  }
  for (int32_t frame = next; frame <= options_.last_frame; ++frame) {
    for (uint32_t i = 0; i < options_.steps_per_frame; ++i) {
      if (cancel_) fail(MOLDTEX_ERROR_CANCELLED, "Cancelled.");
      sim.step(1);
    }
    sim.write_image(frame_path(frame), options_.format);
    moldtex_sim_stats st = sim.stats();
    rows.push_back({frame, 0, st.step_count, st.coverage, st.presence});
    if (options_.write_checkpoints) sim.save_checkpoint(checkpoint_path(), rows);
    write_metrics_csv(rows);
    std::lock_guard<std::mutex> lock(mutex_);
    progress_.frames_done = static_cast<uint32_t>(frame - options_.first_frame + 1);
    progress_.last_frame_written = frame;
    progress_.step_count = st.step_count;
    progress_.coverage = st.coverage;
    progress_.presence = st.presence;
  }
}

void Bake::run() {
  const JobOutcome ended =
      run_job([this] { bake_frames(); }, "Out of memory during the bake", "Internal error during the bake: ");
  // A cancelled bake is no failure: its outcome stays MOLDTEX_OK, with no message.
  const bool cancelled = ended.status == MOLDTEX_ERROR_CANCELLED;
  const uint32_t state = ended.state();
  const moldtex_status outcome = cancelled ? MOLDTEX_OK : ended.status;
  const std::string message = cancelled ? std::string() : ended.message;
  std::lock_guard<std::mutex> lock(mutex_);
  progress_.state = state;
  std::snprintf(progress_.message, sizeof(progress_.message), "%s", message.c_str());
  outcome_ = outcome;
  sim_->busy = false;
}

}  // namespace moldtex
