// The --model presets: the nine MovingCap presets of models.md and the four FAULHABER
// MotionController V3.0 presets of faulhaber.md §1 (drive/model/faulhaber_presets.cpp): identity,
// dictionary base, factory values, plant and I/O. Pure data; the server may copy a preset and apply
// "model_overrides" / "plant" from --config (and, for FAULHABER, faulhaber.serial → identity.serial,
// faulhaber.node_id → factory_values[2400h.03], before the dictionary is built).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mcemu::model {

// The personality a preset belongs to: which dictionary, protocols and drive differences it has
// (faulhaber.md §1, §7). The composition root asks it which services and parts to build.
enum class Family : std::uint8_t { movingcap, faulhaber };
// The dictionary a preset is built from: one of the four Fullmo XDDs, or the hand-written
// FAULHABER table (drive/od/faulhaber_table.cpp).
enum class Base : std::uint8_t { mc349, mc6xx, mcflat, mcn23, faulhaber };
enum class Controller : std::uint8_t { standard, rabbit };
enum class Kind : std::uint8_t { rotary, linear };

struct Identity {
  std::string device_name;       // 1008h
  std::string hardware_version;  // 1009h
  std::string software_version;  // 100Ah
  std::uint32_t vendor_id = 0x053B;
  std::uint32_t product_code = 50;
  std::uint32_t revision = 1;
  std::uint32_t serial = 0x44444444;        // 3404h.04 and 1018h.04
  std::string vendor_name = "Fullmo GmbH";  // EDS export
  std::string short_name;                   // web headings
  std::string display_name;                 // web title
  friend bool operator==(const Identity&, const Identity&) = default;
};

// models.md §4. Rotary: torque N·m, inertia kg·m², B N·m·s/rad, speeds rpm.
// Linear: force N, mass kg, B N·s/m, speeds m/s (no_load_speed) and mm/s (moving_threshold).
// The one list of plant fields: the "plant" section of --config replaces some of them
// (core::PlantOverrides, drive/plant_config.hpp).
struct Plant {
  double torque_peak = 0;
  double torque_cont = 0;
  double inertia_motor = 0;
  double inertia_load = 0;
  double viscous = 0;
  double coulomb = 0;
  double no_load_speed = 0;
  double velocity_bandwidth_hz = 150;
  double accel_feedforward = 0.9;
  std::int64_t following_error_limit_inc = 0;                      // 0 = none
  std::optional<std::pair<std::int64_t, std::int64_t>> stops_inc;  // mechanical stops, raw inc
  std::int64_t power_on_position_inc = 0;
  double moving_threshold = 10;
  bool absolute_encoder = true;
  double p_idle_w = 2;
  double p_cu_w = 40;
  double r_th_k_per_w = 3.0;
  double tau_th_s = 600;
  bool temperature_available = true;
  double supply_nominal_v = 48;
  double supply_uv_v = 18;
  double supply_ov_v = 60;
  bool hw_enable_fitted = false;
  int hw_enable_input = 0;  // 1..10, 0 = the option is a power pin (not an input)
  // rotary acceleration unit as a rational number of motor rev/s² (drive-core.md §3.6)
  std::int64_t rotary_accel_unit_num = 1;
  std::int64_t rotary_accel_unit_den = 36;
  friend bool operator==(const Plant&, const Plant&) = default;
};

struct ObjectKey {
  std::uint16_t index;
  std::uint8_t sub;
  friend auto operator<=>(const ObjectKey&, const ObjectKey&) = default;
};

struct ModelPreset {
  std::string name;  // the --model value
  Family family = Family::movingcap;
  Base base = Base::mc349;
  std::string xdd_file;
  Controller controller = Controller::standard;
  Kind kind = Kind::rotary;
  std::uint32_t supported_modes = 0x25;  // 6502h
  std::uint32_t encoder_inc = 65536;     // 608Fh.01
  bool ae_extras = false;                // 3401h.1F–.25 (MC349_AE)
  Identity identity;
  Plant plant;
  std::vector<int> input_pins;     // IN numbers with a physical pin
  std::vector<int> output_pins;    // OUT numbers with a physical pin
  std::vector<int> combined_pins;  // IOx pins: IN x also sees OUT x
  // per-preset factory values that differ from the all-model table (models.md §3.2)
  std::map<ObjectKey, std::int64_t> factory_values;
  // Values the drive core uses for entries it reads that this family's dictionary does not have
  // (a FAULHABER drive has no 3401h, 6059h, 60F2h …); an absent key reads as 0. Never consulted
  // for an entry the dictionary has.
  std::map<ObjectKey, std::int64_t> core_constants;

  bool is_rabbit() const { return controller == Controller::rabbit; }
  bool is_faulhaber() const { return family == Family::faulhaber; }
  // The MovingCap I/O functions (iofunc/, 3510h–36xxh) exist only on MovingCap drives; a
  // FAULHABER drive is stepped and powered through DriveCore directly.
  bool has_io_functions() const { return family == Family::movingcap; }
  // Every field: equal presets build equal dictionaries (od::preset_layout shares their layout).
  friend bool operator==(const ModelPreset&, const ModelPreset&) = default;
};

// Built-in MovingCap presets, in the order of the README table.
std::span<const std::string_view> preset_names();
// The FAULHABER presets FH_MC5004, FH_MC5005, FH_MC5010, FH_MCS.
std::span<const std::string_view> faulhaber_preset_names();
// Both lists, MovingCap first (what --model accepts).
std::span<const std::string_view> all_preset_names();
// nullopt for an unknown name (names are case-sensitive); finds both families.
std::optional<ModelPreset> find_preset(std::string_view name);
// One FAULHABER preset, nullopt for another name (drive/model/faulhaber_presets.cpp).
std::optional<ModelPreset> find_faulhaber_preset(std::string_view name);
std::string_view to_string(Base b);
std::string_view to_string(Family f);  // "movingcap", "faulhaber"

}  // namespace mcemu::model
