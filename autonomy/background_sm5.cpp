#include "autonomy/background_sm5.h"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <exception>
#include <stdexcept>
#include <utility>

#include "common/wall_clock.h"

namespace mopad::autonomy {

struct BackgroundSm5::Impl {
  struct Job {
    std::unique_ptr<const modelling::RoomModel> model;
    modelling::StructuralModel sm3;
    modelling::Sm4Model sm4;
    modelling::OrthoPoints points;
    Result result;
  };
  RecogniserSource recogniser;
  modelling::ComponentParams params;
  // Two slots: the worker that takes the task, and the owner when it waits in Finish (it
  // helps with the detection's parallel loops then).
  tbb::task_arena arena{2};
  tbb::task_group group;
  std::unique_ptr<Job> job;

  void Wait() {
    arena.execute([this] { group.wait(); });
  }
};

BackgroundSm5::BackgroundSm5(RecogniserSource recogniser, const modelling::ComponentParams& params)
    : impl_(std::make_unique<Impl>()) {
  impl_->recogniser = std::move(recogniser);
  impl_->params = params;
}

BackgroundSm5::~BackgroundSm5() { impl_->Wait(); }

void BackgroundSm5::Prepare() {
  Impl& m = *impl_;
  if (!m.recogniser) return;
  m.arena.execute([&m] {
    m.group.run([&m] {
      try {
        m.recogniser();
      } catch (const std::exception&) {
        // The room's detection asks again and reports it.
      }
    });
  });
}

void BackgroundSm5::Start(std::size_t key, std::unique_ptr<const modelling::RoomModel> model,
                          modelling::StructuralModel sm3, modelling::Sm4Model sm4,
                          modelling::OrthoPoints points) {
  Impl& m = *impl_;
  if (m.job) throw std::logic_error("BackgroundSm5: Start before the last room was collected");
  m.job = std::make_unique<Impl::Job>();
  Impl::Job* job = m.job.get();
  job->model = std::move(model);
  job->sm3 = std::move(sm3);
  job->sm4 = std::move(sm4);
  job->points = std::move(points);
  job->result.key = key;
  job->result.sm5.room = job->sm3.room;
  m.arena.execute([&m, job] {
    m.group.run([&m, job] {
      const auto t0 = WallClock::now();
      try {
        if (const modelling::ComponentRecogniser* r = m.recogniser ? m.recogniser() : nullptr)
          job->result.sm5 =
              modelling::DetectComponents(job->sm3, job->sm4, job->points, *r, m.params);
      } catch (const std::exception& e) {
        job->result.error = e.what();
      }
      job->result.seconds = SecondsSince(t0);
      // The room's points are not needed any more: freed here, not on the robot's thread.
      job->points = {};
      job->model.reset();
    });
  });
}

std::optional<BackgroundSm5::Result> BackgroundSm5::Finish() {
  Impl& m = *impl_;
  if (!m.job) return std::nullopt;
  m.Wait();
  Result out = std::move(m.job->result);
  m.job.reset();
  return out;
}

}  // namespace mopad::autonomy
