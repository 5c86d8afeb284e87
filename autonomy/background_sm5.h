#pragma once
// SM5 of a finished room, computed beside what the robot does next (docs/performance.md).
//
// The robot decides nothing from SM5: the floor mission's tree takes its doors from SM4, and a
// room's SM5 is read only when the mission's files are written. So the component detection of
// the room just left need not hold the robot up: it runs as a TBB task in an arena of its own
// (the worker thread takes it while the robot drives on and scans; the robot's own parallel
// loops keep their arena and never wait on it) and the mission collects it before it starts
// the next room's and at its end. One room at a time.
//
// The result is the one computed in place: DetectComponents is deterministic whatever threads
// run it, and it gets the same SM3, SM4 and points. The room model stays alive (its points are
// the detection's input) until the detection ends and is dropped on the worker.
//
// Robot side. Not thread-safe: one owner calls Start and Finish.

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "modelling/components.h"
#include "modelling/openings.h"
#include "modelling/orthoimage.h"
#include "modelling/room_model.h"
#include "modelling/structural_model.h"

namespace mopad::autonomy {

/// SM5's recogniser, asked for on the thread that runs the detection (so a recogniser trained
/// on first use trains there); nullptr: no SM5.
using RecogniserSource = std::function<const modelling::ComponentRecogniser*()>;

class BackgroundSm5 {
 public:
  /// What the detection of one room gave.
  struct Result {
    std::size_t key = 0;      ///< as given to Start
    modelling::Sm5Model sm5;  ///< empty (its room set) when `error` is set
    double seconds = 0.0;     ///< s of wall time of the detection (reporting only)
    std::string error;        ///< non-empty: the detection failed with this message
  };

  BackgroundSm5(RecogniserSource recogniser, const modelling::ComponentParams& params);
  ~BackgroundSm5();  ///< waits for what still runs (a room's result is dropped)
  BackgroundSm5(const BackgroundSm5&) = delete;
  BackgroundSm5& operator=(const BackgroundSm5&) = delete;

  /// Asks for the recogniser now, beside the owner (one trained on first use trains while the
  /// first room is scanned, not when its SM5 is due). Optional; once, before the first Start.
  void Prepare();
  /// Starts SM5 of the room `key` (sm3.room names it) from `points` (SM4's input, pointing into
  /// `model`, which is kept until the detection ends; null when they point elsewhere). A room
  /// still running must have been collected with Finish first (std::logic_error otherwise).
  void Start(std::size_t key, std::unique_ptr<const modelling::RoomModel> model,
             modelling::StructuralModel sm3, modelling::Sm4Model sm4,
             modelling::OrthoPoints points);
  /// Waits for the room started last, if any, and returns its result (once).
  std::optional<Result> Finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mopad::autonomy
