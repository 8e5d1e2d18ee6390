// Liveness of an owner as its late callbacks see it. Handlers of Asio operations, sessions the
// adapter destroys after their server, and completions of requests can run after the object that
// created them is gone; they capture a Liveness and check alive() before touching it.
//
// The owner holds a LivenessToken (as a member, destroyed with it, or ended early by end()).
// PURE, header-only, single-threaded.
#pragma once

#include <memory>

namespace mcemu::base {

class Liveness {
 public:
  Liveness() = default;
  bool alive() const { return !flag_.expired(); }
  explicit operator bool() const { return alive(); }

 private:
  friend class LivenessToken;
  explicit Liveness(std::weak_ptr<const bool> flag) : flag_(std::move(flag)) {}
  std::weak_ptr<const bool> flag_;
};

class LivenessToken {
 public:
  LivenessToken() = default;
  LivenessToken(const LivenessToken&) = delete;
  LivenessToken& operator=(const LivenessToken&) = delete;

  Liveness watch() const { return Liveness(flag_); }
  bool alive() const { return flag_ != nullptr; }
  // Every Liveness watching this token reports dead from now on.
  void end() { flag_.reset(); }

 private:
  std::shared_ptr<const bool> flag_ = std::make_shared<const bool>(true);
};

}  // namespace mcemu::base
