// The four receive PDOs (slcan-canopen.md §9.6): mapped values written through the OD with origin
// `sdo`, at once (254/255) or at the next SYNC (0…240); length errors reported by EMCY 8210h /
// 8220h once and cleared by EMCY 0000h. Processed only in OPERATIONAL (the node filters). Pure.
// A PDO is one consistent set of values: the controlword 6040h is written after the other mapped
// values of the same PDO, so that its set-point edge sees the target of that PDO (RPDO3
// `t43261F0030750000`, PDO-27; docs/decisions/0004).
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "protocols/can/frame.hpp"

namespace mcemu::canopen {

class RpdoSet {
 public:
  struct Hooks {
    std::function<void(std::uint16_t code, std::uint8_t register_bits)> emcy;
    std::function<void()> after_write;
    std::function<void(const std::string&)> diagnostic;
  };
  RpdoSet(od::ObjectDictionary& od, Hooks hooks) : od_(od), hooks_(std::move(hooks)) {}

  // A data frame; true if it matched a valid RPDO.
  bool on_frame(const can::Frame& frame);
  // SYNC: buffered synchronous RPDOs are applied in ascending number.
  void on_sync();
  void leave_operational();  // buffered data discarded
  void reset();              // also the length-error states

 private:
  enum class LengthState : std::uint8_t { ok, too_short, too_long };
  struct State {
    LengthState length = LengthState::ok;
    std::optional<std::vector<std::uint8_t>> buffered;
  };
  void apply(int n, const std::vector<std::uint8_t>& data);
  void length_emcy(State& s, LengthState next);

  od::ObjectDictionary& od_;
  Hooks hooks_;
  std::array<State, 4> state_{};
};

}  // namespace mcemu::canopen
