#include "runtime/stepped_run.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "compile/device_setup.hpp"
#include "core/error.hpp"
#include "core/reproducible.hpp"
#include "runtime/devices.hpp"
#include "runtime/loop_set.hpp"
#include "runtime/recorder.hpp"

namespace tactus::runtime {

SteppedRun::SteppedRun(const scene::Model& model, SessionOptions options, const std::vector<std::string>& controlled)
    : model_(model), options_(std::move(options)), controlled_(model.devices.size(), nullptr) {
  fix_dense_blocking();  // as run_session: lockstep runs sum alike on every machine
  fix_blas_threads();
  options_.scheduling = Scheduling::lockstep;
  options_.interrupt = nullptr;
  options_.visual = nullptr;
  check_runnable(model_, options_);
  std::vector<bool> wanted(model_.devices.size(), false);
  for (const std::string& name : controlled) {
    const scene::Device* d = model_.find_device(name);
    if (!d)
      throw InputError(SourceLocation{model_.source, {}, {}, {}},
                       fmt::format("no device '{}' to control in this scene", name));
    wanted[static_cast<std::size_t>(d - model_.devices.data())] = true;
  }
  // The controlled devices replace the scene's entries; the loops own them, this run keeps
  // their addresses to set poses.
  auto scene_override = options_.device_override;
  options_.device_override = [this, wanted, scene_override](const scene::Model& m,
                                                            std::size_t i) -> std::unique_ptr<haptics::Device> {
    if (wanted[i]) {
      auto device = std::make_unique<ControlledDevice>(compile::device_limits(m.devices[i]));
      controlled_[i] = device.get();
      return device;
    }
    return scene_override ? scene_override(m, i) : nullptr;
  };
  loops_ = std::make_unique<Loops>(build_loops(model_, options_));
  start_report(model_, options_, *loops_, report_);
  recorder_ = std::make_unique<Recorder>(model_, options_, loops_->channel_ptrs(), loops_->simulation->steps(), report_);
  if (loops_->vtk) recorder_->add_vtk(*loops_->vtk, *loops_->nodes);
}

SteppedRun::~SteppedRun() {
  // A run dropped without finish() still closes its recording.
  if (!finished_) try {
      recorder_->close();
    } catch (...) {
    }
}

double SteppedRun::time() const {
  return frames_ == 0 ? 0.0 : static_cast<double>(frames_ - 1) / model_.rates.haptic;
}

void SteppedRun::step() {
  if (finished_) throw std::logic_error("the run has finished: it steps no more");
  const Nanos wall0 = now_ns();
  // The instants run_lockstep visits: k / rate, never an accumulated sum.
  const double t = static_cast<double>(frames_) / model_.rates.haptic;
  LockstepCursor cursor{simulation_steps_, interaction_steps_};
  lockstep_catch_up(model_, *loops_, *recorder_, cursor, t);
  simulation_steps_ = cursor.simulation_steps;
  interaction_steps_ = cursor.interaction_steps;
  lockstep_haptic_frames(*loops_, t);
  recorder_->drain();
  ++frames_;
  wall_ += now_ns() - wall0;
}

void SteppedRun::set_pose(std::size_t device, const haptics::DevicePose& pose) {
  if (!controlled(device))
    throw std::invalid_argument(fmt::format("device {} is not controlled by the caller", device));
  controlled_[device]->set_pose(pose);
}

bool SteppedRun::controlled(std::size_t device) const {
  return device < controlled_.size() && controlled_[device] != nullptr;
}

const std::vector<HapticFrame>& SteppedRun::latest_frames() const { return recorder_->latest_frames(); }

const VecX* SteppedRun::positions(std::size_t body) const { return loops_->simulation->positions(body); }

void SteppedRun::emergency_stop() {
  for (auto& h : loops_->haptic) h->request_emergency_stop();
}

SessionReport SteppedRun::finish() {
  if (finished_) throw std::logic_error("the run has already finished");
  finished_ = true;
  report_.simulated_time = time();
  report_.wall_time = static_cast<double>(wall_) * 1e-9;
  recorder_->close();
  complete_report(model_, *loops_, report_);
  return std::move(report_);
}

}  // namespace tactus::runtime
