// Text forms of everything observable about a drive, for the "catch-up = 1 ms stepping" tests:
// every object value as a read returns it (read hooks included) and every core event.
#pragma once

#include <cstdio>
#include <string>
#include <variant>
#include <vector>

#include "drive/events.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::sim::test {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

inline std::string event_text(const core::Event& e) {
  const auto n = [](auto v) { return std::to_string(static_cast<long long>(v)); };
  return std::visit(
      Overloaded{
          [&](const core::StatuswordChanged& x) { return "sw " + n(x.old_value) + ">" + n(x.new_value); },
          [&](const core::StateChanged& x) {
            return "state " + n(static_cast<int>(x.from)) + ">" + n(static_cast<int>(x.to)) + " t" + n(x.transition);
          },
          [&](const core::ModeDisplayChanged& x) { return "mode " + n(x.mode); },
          [&](const core::Emcy& x) {
            std::string s = "emcy";
            for (auto b : x.bytes()) {
              s += ' ';
              s += n(b);
            }
            return s;
          },
          [&](const core::FaultRaised& x) { return "fault " + n(x.code); },
          [&](const core::FaultResetDone&) { return std::string("reset"); },
          [&](const core::FaultResetRefused& x) { return "refused " + n(x.causes.size()); },
          [&](const core::SetpointAccepted& x) { return "accepted " + n(x.target_inc) + " " + n(x.buffered); },
          [&](const core::SetpointRejected&) { return std::string("rejected"); },
          [&](const core::TargetReached& x) { return "reached " + n(x.mode); },
          [&](const core::HomingFinished& x) { return "homed " + n(x.method) + " " + n(x.ok); },
          [&](const core::InternalLimit& x) { return "limit " + n(x.active); },
          [&](const core::InputsChanged& x) { return "inputs " + n(x.old_value) + ">" + n(x.new_value); },
          [&](const core::PowerStage& x) { return "power " + n(x.on); },
          [&](const core::Diagnostic& x) { return "diag " + x.text; },
      },
      e);
}

// "6041.00=39" for every entry, in dictionary order, as read() returns it.
inline std::vector<std::string> od_dump(const od::ObjectDictionary& od) {
  std::vector<std::string> out;
  od.for_each([&](const od::EntryInfo& info, const od::Value&) {
    char key[16];
    std::snprintf(key, sizeof key, "%04X.%02X=", info.index, info.sub);
    const auto v = od.read(info.index, info.sub);
    std::string text;
    if (!v) {
      text = "abort";
    } else if (const auto* i = std::get_if<std::int64_t>(&*v)) {
      text = std::to_string(*i);
    } else {
      text = std::get<std::string>(*v);
    }
    out.push_back(key + text);
  });
  return out;
}

}  // namespace mcemu::sim::test
