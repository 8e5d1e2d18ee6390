// The simulated drive (drive-core.md): CiA 402 state machine, profile position / velocity / homing
// on a physical plant, scaling, soft limits, faults and EMCY. One core serves both families of
// presets: a MovingCap drive, and a FAULHABER MotionController with the drive differences of
// faulhaber.md §7 (drive_core_faulhaber.cpp) — chosen by ModelPreset::family, nothing else.
//
// Contract:
// - Pure and single-threaded: no clock, I/O, threads, logging or randomness. Time moves only by
//   step() / advance() in 1 ms steps, in the order of §2.4.
// - The OD is the only store (§1.3). The constructor registers the core's write and read hooks
//   (§14) on the dictionary, which must outlive the core; the core is not powered until
//   power_on(). A write of 6040h acts inside the write call (§2.5); 6041h is current when it returns.
// - Events (§13) queue up until drain_events(); the inputs observer is called synchronously on
//   every change of 60FDh and must not write objects.
// - Not copyable or movable (hooks capture `this`); the destructor removes the hooks again.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "drive/core_context.hpp"
#include "drive/core_types.hpp"
#include "drive/events.hpp"
#include "drive/faulhaber/fh_objects.hpp"
#include "drive/faults.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/modes/homing.hpp"
#include "drive/modes/profile_position.hpp"
#include "drive/modes/profile_velocity.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/settings_cache.hpp"
#include "drive/plant.hpp"
#include "drive/plant_config.hpp"
#include "drive/step_count.hpp"
#include "drive/thermal.hpp"

namespace mcemu::core {

using InputsObserver = std::function<void(std::uint32_t old_60fd, std::uint32_t new_60fd)>;

class DriveCore {
 public:
  // Throws std::invalid_argument for an invalid plant configuration (resolve_plant()).
  DriveCore(const model::ModelPreset& preset, od::ObjectDictionary& od, const PlantConfig& plant_config = {});
  ~DriveCore();  // removes the hooks it registered
  DriveCore(const DriveCore&) = delete;
  DriveCore& operator=(const DriveCore&) = delete;

  // ---- lifecycle and time (§2, §4.4)
  void power_on(const PowerOnState& state = {});  // transition 0; the OD image is loaded before
  void reload_parameters();                       // recompute caches after a bulk OD load
  void step();                                    // one 1 ms step
  void step(std::uint64_t n);                     // n steps
  void advance(std::chrono::milliseconds dt) { step(static_cast<std::uint64_t>(dt.count())); }
  std::uint64_t time_ms() const { return ctx_.time_ms; }

  // ---- idle: "time is asked, not polled" (design.md; drive_core_quiet.cpp)
  static constexpr std::uint64_t k_forever = UINT64_MAX;
  // How many of the next steps would change nothing but what skip() reproduces (drive time, the
  // supply debounce counters, the thermal model): 0 = the next step must run; k_forever = never
  // (not powered, or at rest with a constant thermal state). Today only a drive at rest with the
  // power stage off (SOD, RTSO, SO, Fault) can be quiet; an enabled drive needs every step.
  // Claims quiet only right after step() or skip(): any write hook, injection or other command
  // in between makes it 0 until the next step.
  std::uint64_t quiet_steps() const;
  // n ≤ quiet_steps() steps at once, leaving exactly the state (and the OD) of n step() calls.
  void skip(std::uint64_t n);

  // ---- queries, no side effects
  PdsState state() const { return state_; }
  bool powered() const { return powered_; }
  // the plant's position (without measurement noise), for the plant-state file
  std::int64_t raw_position_inc() const;
  std::int64_t home_offset_inc() const { return ctx_.home_offset_inc; }
  std::int64_t last_internal_target_inc() const;
  std::optional<std::int64_t> last_setpoint_target_inc() const { return pp_.last_setpoint_target_inc(); }
  bool torque_on() const { return torque_on_; }
  double temperature_c() const;   // as the monitors and 3401h.0Ah see it
  double supply_voltage() const;  // as the monitors see it
  double i2t_energy() const { return thermal_.energy(); }
  double i2t_energy_max() const { return thermal_.energy_max(); }
  bool injected(FaultCause cause) const { return (injected_ >> static_cast<int>(cause)) & 1u; }
  const PlantParams& plant_params() const { return params_; }
  // the current unit conversions (§3), for components that report in user units (iofunc)
  const Scaling& scaling() const { return ctx_.scaling; }
  // Software Enable condition of §4.6 on the current 60FDh (true when no input has function 9)
  bool software_enabled() const { return sw_enable_ok(); }
  // the actual velocity of the last step in inc/s (the footer's motor rpm, web.md §4.2)
  double actual_velocity_inc_s() const { return ctx_.actual_velocity_inc_s; }
  // the wire levels of IN1…IN10 as bits 16…25 (60FDh without 3510h.01): simulation-API levels,
  // position switches and combined-pin feedback (iofunc.md §2.1; web.md §8.5 "physical")
  std::uint32_t physical_inputs() const;
  // The fault and warning bits in the 1002h layout of drive/faults.hpp (bit 0 over-voltage …, 16
  // sensor warning): 1002h itself on a MovingCap drive; kept by the core on a FAULHABER drive,
  // which has no 1002h (it shows them as 2320h, faulhaber.md §8).
  std::uint32_t fault_bits() const { return static_cast<std::uint32_t>(mfr()); }
  // FAULHABER: the temperature warning (2320h bit 4) is on; always false on a MovingCap drive.
  bool temperature_warning() const { return fh_temperature_warning_; }

  // ---- commands used by the helpers (§12)
  void apply_mode_switch_now();      // §6.3 at once
  void resume_interrupted_motion();  // CM / ContinueMotion
  od::AbortCode set_home_here();     // §9.3

  // ---- fault and environment injection (§11.9)
  void inject(FaultCause cause);
  void clear(FaultCause cause);
  void set_supply_voltage(double volts);
  void set_ambient_temperature(double deg_c);
  void set_external_load(double nm_or_n);
  ObstacleId add_obstacle(const Obstacle& obstacle);
  void remove_obstacle(ObstacleId id);
  bool set_external_input_level(int input, bool high);  // false: no such pin on the model
  // All input levels at once, bit n−1 = input n (FAULHABER: DigIn n, what 2311h.02 shows); one
  // recomputation. false and nothing changed when a bit names an input without a pin.
  bool set_external_input_levels(std::uint32_t levels);
  void connection_lost();  // §11.6
  // §11.8 mcdrive.SendEmcyMsg: an EMCY with bytes code, register, error number (u32 LE), 0.
  // Changes no object and no state.
  void send_script_emcy(std::uint32_t error_number, std::uint8_t error_register = 0, std::uint16_t error_code = 0x509B);

  // ---- inputs (§10.9)
  void recompute_inputs();
  // One observer (the I/O functions); others watch 60FDh through the OD change listener. A second
  // registration throws std::logic_error instead of silently replacing the first.
  void set_inputs_observer(InputsObserver observer) {
    if (observer_ && observer) throw std::logic_error("a second inputs observer on the drive core");
    observer_ = std::move(observer);
  }

  // ---- events (§13)
  std::vector<Event> drain_events();

 private:
  enum class Pending : std::uint8_t { none, to_switched_on, to_ready, to_disabled, to_fault };

  // drive_core.cpp
  void install_hooks();
  std::int64_t mfr() const;         // 1002h, or the core's own bits where the family has no 1002h
  void set_mfr(std::int64_t bits);  // the same, written
  void hook_write(std::uint16_t index, std::uint8_t sub, od::WriteHook hook);
  void hook_read(std::uint16_t index, std::uint8_t sub, od::ReadHook hook);
  FactorGroup stored_factor_group() const;  // 608Fh/6091h/6092h/607Eh as stored
  void update_scaling();
  void update_inertia_ctrl(std::optional<std::int64_t> weight, std::optional<std::int64_t> payload);
  // drive_core_pds.cpp
  od::AbortCode on_controlword(std::uint16_t cw, std::uint16_t prev);
  void apply_state_command(std::uint16_t cw);
  void set_state(PdsState to, int transition);
  void enter_operation_enabled(int transition);
  void leave_operation_enabled();
  void set_torque(bool on);
  void begin_stop(Pending pending, double decel);
  void quick_stop();
  void finish_pending();
  bool switch_on_allowed();
  bool sw_enable_ok() const;
  bool hw_enable_ok() const;
  void raise(FaultCause cause);
  void enter_fault_reaction(bool torque_off);
  void try_fault_reset();
  bool reset_allowed(FaultCause cause) const;
  void record_history(std::uint16_t code);
  void check_conditions();
  void check_enable_loss();
  void timed_transitions();
  void on_block_detected(bool masked);
  void stroke_reaction();
  void after_homing();
  // drive_core_faulhaber.cpp (FAULHABER family only, faulhaber.md §7–§8)
  void install_faulhaber_hooks();
  void fh_power_on();
  void fh_publish_inputs();
  void fh_apply_input_config(const faulhaber::InputConfig& config);
  faulhaber::InputConfig fh_input_config() const;
  std::uint32_t fh_device_status() const;  // 2324h.01 from the present state
  void fh_publish_status();
  void fh_raise(FaultCause cause, std::int64_t next_bits);
  void fh_fault_reset_done(std::int64_t bits);
  void fh_check_temperature_warning();
  void fh_limit_switch_guard();
  std::pair<double, double> fh_torque_limits() const;  // N·m (positive, negative direction)
  bool fh_emcy_enabled(int error_bit) const;           // 2321h.01 lets this 2320h bit's EMCY through
  // drive_core_step.cpp
  void mode_switch();
  void mode_switch_to(std::int8_t requested);
  void enter_mode(std::int8_t mode);
  void leave_mode(std::int8_t mode);
  void generate();
  void run_plant();
  void monitors();
  void thermal_step();
  std::int64_t next_noise();
  void finish_write();
  // drive_core_quiet.cpp
  bool resting() const;
  std::uint64_t thermal_quiet_steps() const;
  // drive_core_outputs.cpp
  std::uint32_t compute_inputs() const;
  void publish_inputs(bool report);
  void write_actuals();
  void write_velocity_objects();
  std::uint16_t compose_statusword() const;
  void update_statusword();
  void install_read_hooks();
  double torque_limit() const;
  int motion_phase() const;  // 0 constant/standstill, 1 accelerating, 2 decelerating

  model::ModelPreset preset_;
  PlantParams params_;
  CoreContext ctx_;
  Plant plant_;
  Thermal thermal_;
  ProfilePosition pp_;
  ProfileVelocity pv_;
  Homing hm_;

  bool powered_ = false;
  PdsState state_ = PdsState::not_ready_to_switch_on;
  bool torque_on_ = false;
  Pending pending_ = Pending::none;
  int pending_transition_ = 0;
  int quick_stop_option_ = 1;
  bool service_move_ = false;  // stroke option 1–3 motion owns the generator
  bool stroke_hold_ = false;   // after a stroke-option stop: hold until a new command
  std::int8_t mode_ = 0;       // 6061h
  std::uint16_t statusword_ = 0;
  bool reached_bit_ = false;
  bool limit_bit_ = false;
  WindowTimer hold_timer_;  // mode 0 held-position rule
  bool hold_reached_ = false;
  Kinematics demand_prev_;

  // environment
  std::optional<double> supply_set_;
  double ambient_c_ = 25;
  std::array<bool, 11> external_level_{};
  // FAULHABER: the objects of faulhaber.md §8 the core maintains (nullopt on a MovingCap drive)
  std::optional<faulhaber::FhHandles> fh_;
  std::int64_t mfr_bits_ = 0;  // fault bits where the dictionary has no 1002h
  bool fh_temperature_warning_ = false;
  std::uint32_t injected_ = 0;  // bit = FaultCause
  std::uint32_t deferred_ = 0;  // event causes injected before the second step
  StepCount uv_count_;          // steps below the under-voltage threshold (saturating: weeks of it)
  StepCount ov_count_;
  bool first_step_ = false;

  // monitors
  int block_count_ = 0;
  int following_count_ = 0;
  PlantOutput plant_out_;
  std::int64_t current_permille_ = 0;
  double prev_position_inc_ = 0;
  std::int64_t prev_reported_inc_ = 0;
  std::uint64_t noise_state_ = 0;
  double dc_link_v_ = 0;
  std::uint64_t fault_reset_prev_ = 0;

  // idle (quiet_steps): set at the end of step()/skip(), cleared by every other mutating call
  bool settled_ = false;
  std::uint64_t settled_generation_ = 0;
  std::uint64_t settle_count_ = 0;  // full steps; a cached prediction belongs to one of them
  mutable std::optional<std::pair<std::uint64_t, std::uint64_t>> quiet_cache_;  // (settle_count_, quiet until)
  // The inputs the input functions 3511h…351Ah require high and low for Software Enable, as bits of
  // CoreContext::inputs (issue 26: ten scattered reads every step of a fleet's drives).
  struct EnableMasks {
    std::uint32_t high = 0;
    std::uint32_t low = 0;
  };
  mutable od::SettingsCache<EnableMasks> enable_masks_;

  InputsObserver observer_;
  std::vector<std::pair<std::uint16_t, std::uint8_t>> write_hooks_;
  std::vector<std::pair<std::uint16_t, std::uint8_t>> read_hooks_;
};

}  // namespace mcemu::core
