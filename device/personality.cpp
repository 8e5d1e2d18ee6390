#include "device/personality.hpp"

namespace mcemu::device {

const Personality& movingcap() {
  static const Personality p{
      .name = "movingcap",
      .refgo = true,
      .canopen = true,
      .udp_debug = true,
      .drive_pages = true,
      .code_scripts = true,
      .io_functions = true,
      .morse_status_led = true,
  };
  return p;
}

const Personality& faulhaber() {
  static const Personality p{
      .name = "faulhaber",
      .faulhaber = true,
      .basic = true,
  };
  return p;
}

const Personality& personality_of(const model::ModelPreset& preset) {
  return preset.is_faulhaber() ? faulhaber() : movingcap();
}

}  // namespace mcemu::device
