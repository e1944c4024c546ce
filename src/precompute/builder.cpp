#include "precompute/builder.hpp"

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "physics/fem/nodal_pressure.hpp"
#include "precompute/model_identity.hpp"
#include "precompute/wavefront.hpp"

namespace tactus::precompute {

Space make_space(const physics::Body& body, const SpaceSettings& settings, std::string scene_text) {
  Space space;
  space.settings = settings;
  const Vec3 contact = body.model->rest_positions().segment<3>(3 * static_cast<Eigen::Index>(settings.contact_node));
  space.grid = Grid::through(contact, settings.bounds_min, settings.bounds_max, settings.spacing);
  space.start = space.grid.nearest(contact);
  space.identity = identify(body, settings, space.grid);
  space.scene_text = std::move(scene_text);
  space.rest_positions = body.model->rest_positions();
  if (const auto* fem = physics::tet_fem_of(body.model.get()))
    for (const auto& e : fem->elements()) space.elements.push_back(e.nodes);
  space.allocate(body.model->node_count());
  return space;
}

Vec3 patch_position(const Space& space, std::size_t point) { return space.position(point); }

PointResult run_task(ConfigurationSolver& solver, const Space& space, std::size_t point, std::int64_t source,
                     const VecX& source_displacement) {
  // The start point is the undeformed contact point itself, not its grid position rounded.
  if (source < 0) return solver.solve_start(point, solver.contact_rest());
  return solver.transition(point, source, source_displacement,
                           patch_position(space, static_cast<std::size_t>(source)), patch_position(space, point));
}

void note_tries(PointResult& r, int failed_tries) {
  if (r.status == PointStatus::failed && failed_tries > 1)
    r.reason += " (the last of " + std::to_string(failed_tries) + " neighbours it was tried from)";
}

PointResult unreachable_result(std::size_t point) {
  PointResult r;
  r.point = point;
  r.status = PointStatus::unreachable;
  r.reason = "every neighbour it can be reached from failed";
  return r;
}

BuildStats build_local(Space& space, const SolverFactory& make_solver, const BuildOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  BuildStats stats;
  stats.workers = std::max(1u, options.threads);
  Wavefront wave(space.grid, space.start, space.status);
  std::mutex mutex;
  std::condition_variable changed;
  std::exception_ptr error;
  bool stop = false;

  // Under the lock: record an outcome (unless the point is to be tried again from another
  // neighbour) and whatever it made unreachable.
  auto record = [&](PointResult& r) {
    ++stats.computed;
    stats.solve_seconds += r.seconds;
    if (wave.complete(r.point, r.status)) {
      note_tries(r, wave.failed_tries(r.point));
      space.store(r);
      if (options.on_result) options.on_result(r);
    } else {
      ++stats.retried;
    }
    for (auto p : wave.take_unreachable()) {
      const PointResult u = unreachable_result(p);
      space.store(u);
      ++stats.unreachable;
      if (options.on_result) options.on_result(u);
    }
    if (options.stop_after > 0 && stats.computed >= options.stop_after && !wave.finished()) {
      stop = true;
      stats.stopped = true;
    }
    if (options.on_progress) options.on_progress(wave.resolved(), space.status.size());
  };
  {
    // A resumed build may start with points already known to be unreachable.
    for (auto p : wave.take_unreachable()) {
      const PointResult u = unreachable_result(p);
      space.store(u);
      ++stats.unreachable;
      if (options.on_result) options.on_result(u);
    }
  }

  auto worker = [&] {
    try {
      auto solver = make_solver();
      VecX source_displacement;
      for (;;) {
        Task task;
        {
          std::unique_lock lock(mutex);
          std::optional<Task> next;
          changed.wait(lock, [&] {
            if (stop || error || wave.finished()) return true;
            next = wave.next();
            return next.has_value() || wave.in_flight() == 0;
          });
          if (!next) {
            // Nothing ready and nothing running: the build is finished (or stopped).
            changed.notify_all();
            return;
          }
          task = *next;
          if (task.source >= 0)
            source_displacement = space.displacement.col(static_cast<Eigen::Index>(task.source));
        }
        PointResult r = run_task(*solver, space, task.point, task.source, source_displacement);
        std::lock_guard lock(mutex);
        record(r);
        changed.notify_all();
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      if (!error) error = std::current_exception();
      changed.notify_all();
    }
  };

  if (stats.workers == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (unsigned i = 0; i < stats.workers; ++i) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  if (error) std::rethrow_exception(error);
  stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace tactus::precompute
