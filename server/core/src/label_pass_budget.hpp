#pragma once
// How much of the fusion thread late label passes may take while frames wait: half the time the
// integrations take, on average. Each integration earns the passes half its duration (the credit
// held at most one integration's worth), each pass spends what it took, and passes stop while the
// credit is used up. With no frame waiting every queued pass runs and nothing is saved for later.
// The map so keeps two thirds of the thread however fast segmentations come.
#include <algorithm>
#include <chrono>

namespace semfuse {

class LabelPassBudget {
 public:
  using Duration = std::chrono::steady_clock::duration;

  // An integration that took `integrating` just ended.
  void earn(Duration integrating) { credit_ = std::min(credit_ + integrating / 2, integrating); }
  // Whether the next pass may run now.
  bool allows(bool frames_wait) {
    if (!frames_wait) credit_ = Duration::zero();
    return !frames_wait || credit_ > Duration::zero();
  }
  // A pass that took `passing` ran.
  void spend(bool frames_wait, Duration passing) {
    if (frames_wait) credit_ -= passing;
  }
  Duration credit() const { return credit_; }

 private:
  Duration credit_{0};
};

}  // namespace semfuse
