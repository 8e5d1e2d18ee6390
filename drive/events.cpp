#include "drive/events.hpp"

#include <array>
#include <cstdio>

namespace mcemu::core {

namespace {

std::string digits(std::uint32_t v, int n) {
  std::array<char, 16> buf{};
  std::snprintf(buf.data(), buf.size(), "%0*X", n, static_cast<unsigned>(v));
  return buf.data();
}

std::string hex(std::uint32_t v, int n) { return digits(v, n) + "h"; }

std::string names(const std::vector<FaultCause>& causes) {
  std::string out;
  for (const auto c : causes) {
    if (!out.empty()) out += ',';
    out += to_string(c);
  }
  return out;
}

struct Text {
  std::string operator()(const StatuswordChanged& e) const {
    return "StatuswordChanged " + hex(e.old_value, 4) + " -> " + hex(e.new_value, 4);
  }
  std::string operator()(const StateChanged& e) const {
    return "StateChanged " + std::string(to_string(e.from)) + " -> " + std::string(to_string(e.to)) + " (transition " +
           std::to_string(e.transition) + ")";
  }
  std::string operator()(const ModeDisplayChanged& e) const { return "ModeDisplayChanged " + std::to_string(e.mode); }
  std::string operator()(const Emcy& e) const {
    std::string data;
    for (const auto b : e.bytes()) data += digits(b, 2);
    return "Emcy " + hex(e.code, 4) + " reg " + hex(e.reg, 2) + " data " + data;
  }
  std::string operator()(const FaultRaised& e) const {
    return "FaultRaised " + std::string(to_string(e.cause)) + " " + hex(e.code, 4);
  }
  std::string operator()(const FaultResetDone&) const { return "FaultResetDone"; }
  std::string operator()(const FaultResetRefused& e) const { return "FaultResetRefused " + names(e.causes); }
  std::string operator()(const SetpointAccepted& e) const {
    return "SetpointAccepted " + std::to_string(e.target_inc) + (e.buffered ? " buffered" : "");
  }
  std::string operator()(const SetpointRejected&) const { return "SetpointRejected buffer_full"; }
  std::string operator()(const TargetReached& e) const { return "TargetReached mode " + std::to_string(e.mode); }
  std::string operator()(const HomingFinished& e) const {
    return "HomingFinished method " + std::to_string(e.method) + (e.ok ? " ok" : " failed");
  }
  std::string operator()(const InternalLimit& e) const {
    return std::string("InternalLimit ") + (e.active ? "on" : "off");
  }
  std::string operator()(const InputsChanged& e) const {
    return "InputsChanged " + hex(e.old_value, 8) + " -> " + hex(e.new_value, 8);
  }
  std::string operator()(const PowerStage& e) const { return std::string("PowerStage ") + (e.on ? "on" : "off"); }
  std::string operator()(const Diagnostic& e) const {
    static constexpr std::array<const char*, 3> k_levels{"debug", "info", "warning"};
    return std::string("Diagnostic ") + k_levels[static_cast<std::size_t>(e.level)] + " " + e.text;
  }
};

}  // namespace

std::string event_text(const Event& e) { return std::visit(Text{}, e); }

}  // namespace mcemu::core
