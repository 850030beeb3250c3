// Readiness: where sweepd is in its life, for the HTTP side port's /readyz — set by main
// (restoring the store, binding the default model, opening the listeners) and by the Server
// (accepting once its I/O thread runs, draining from SIGTERM on). Safe to read and set from
// any thread (one atomic).
// ready(): true only while accepting. describe(stage): a word for the stage, e.g. "draining".
// on_change (optional, given at construction): called by set() after the stage is stored, on
// the setting thread — so an observer told "accepting" (systemd's READY=1, SystemdNotifier)
// is told it only once /readyz already answers 200.
#pragma once

#include <atomic>
#include <functional>
#include <utility>

namespace sweepd::server {

class Readiness {
 public:
  enum class Stage {
    kRestoringStore,
    kBindingDefaultModel,
    kOpeningListeners,
    kAccepting,
    kDraining
  };

  explicit Readiness(std::function<void(Stage)> on_change = {})
      : on_change_(std::move(on_change)) {}

  void set(Stage stage) {
    stage_.store(stage, std::memory_order_release);
    if (on_change_) on_change_(stage);
  }
  Stage stage() const { return stage_.load(std::memory_order_acquire); }
  bool ready() const { return stage() == Stage::kAccepting; }

  static const char* describe(Stage stage) {
    switch (stage) {
      case Stage::kRestoringStore:
        return "restoring the model store";
      case Stage::kBindingDefaultModel:
        return "binding the default model";
      case Stage::kOpeningListeners:
        return "opening the listeners";
      case Stage::kAccepting:
        return "accepting";
      case Stage::kDraining:
        return "draining (shutting down)";
    }
    return "unknown";
  }

 private:
  std::atomic<Stage> stage_{Stage::kRestoringStore};
  const std::function<void(Stage)> on_change_;
};

}  // namespace sweepd::server
