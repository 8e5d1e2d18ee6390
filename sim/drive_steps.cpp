#include "sim/drive_steps.hpp"

#include <algorithm>

namespace mcemu::sim {

DriveSteps::DriveSteps(od::ObjectDictionary& od, iofunc::IoFunctions* io, core::DriveCore& core)
    : od_(od), io_(io), core_(core) {}

void DriveSteps::step() {
  const std::uint64_t before = od_.generation();
  dirty_ = false;
  if (io_) {
    io_->step();
  } else {
    core_.step();
  }
  for (Part* p : parts_) p->step();
  generation_ = od_.generation();
  // A step that changed the dictionary (a moving drive changes its actual values every step) is
  // taken as "not quiet" for the next one without asking the parts: 0 is always a correct answer
  // (a step is never wrong), and asking costs a moving fleet ~10 % per step. A drive that has just
  // come to rest pays one full step more.
  changed_ = generation_ != before;
}

std::uint64_t DriveSteps::quiet_steps() const {
  if (dirty_ || changed_ || od_.generation() != generation_) return 0;
  std::uint64_t q = io_ ? io_->quiet_steps() : core_.quiet_steps();
  for (const Part* p : parts_) {
    if (q == 0) break;
    q = std::min(q, p->quiet_steps());
  }
  return q;
}

void DriveSteps::skip(std::uint64_t n) {
  if (n == 0) return;
  if (io_) {
    io_->skip(n);
  } else {
    core_.skip(n);
  }
  for (Part* p : parts_) p->skip(n);
}

void DriveSteps::prefetch(int level) const {
  switch (level) {
    case 0:
      __builtin_prefetch(&od_);
      __builtin_prefetch(&core_);
      __builtin_prefetch(io_);
      __builtin_prefetch(parts_.data());
      break;
    case 1:
      od_.prefetch();
      for (const Part* p : parts_) __builtin_prefetch(p);
      break;
    default:
      for (const Part* p : parts_) p->prefetch();
      break;
  }
}

std::uint64_t DriveSteps::next_deadline_ms() const {
  const std::uint64_t q = quiet_steps();
  return q == k_forever ? k_forever : time_ms() + q + 1;
}

Advanced DriveSteps::advance_to(std::uint64_t t, std::uint64_t max_full) {
  if (t <= time_ms()) return {};
  return advance(*this, t - time_ms(), max_full);
}

}  // namespace mcemu::sim
