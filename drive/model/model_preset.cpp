#include "drive/model/model_preset.hpp"

#include <array>

namespace mcemu::model {
namespace {

constexpr std::array<std::string_view, 9> k_names = {"MC349", "MC349_AE", "MCN23", "MCFLAT",   "MCSHORT",
                                                     "MC632", "MC634",    "MC636", "PUSHTRACK"};
constexpr std::array<std::string_view, 13> k_all_names = {"MC349",     "MC349_AE",  "MCN23", "MCFLAT",    "MCSHORT",
                                                          "MC632",     "MC634",     "MC636", "PUSHTRACK", "FH_MC5004",
                                                          "FH_MC5005", "FH_MC5010", "FH_MCS"};

Identity identity(std::string device, std::string sw, std::uint32_t product, std::string short_name,
                  std::string display) {
  Identity id;
  id.device_name = std::move(device);
  id.hardware_version = "V1.00";
  id.software_version = std::move(sw);
  id.product_code = product;
  id.short_name = std::move(short_name);
  id.display_name = std::move(display);
  return id;
}

struct PlantRow {
  double peak, cont, inertia, viscous, coulomb, no_load, bandwidth;
  std::int64_t fe_limit;
  std::optional<std::pair<std::int64_t, std::int64_t>> stops;
  std::int64_t power_on;
  double moving;
  bool absolute;
  double p_idle, p_cu, r_th, tau;
  bool temperature;
  double supply;
};

Plant plant(const PlantRow& r) {
  Plant p;
  p.torque_peak = r.peak;
  p.torque_cont = r.cont;
  p.inertia_motor = r.inertia;
  p.viscous = r.viscous;
  p.coulomb = r.coulomb;
  p.no_load_speed = r.no_load;
  p.velocity_bandwidth_hz = r.bandwidth;
  p.following_error_limit_inc = r.fe_limit;
  p.stops_inc = r.stops;
  p.power_on_position_inc = r.power_on;
  p.moving_threshold = r.moving;
  p.absolute_encoder = r.absolute;
  p.p_idle_w = r.p_idle;
  p.p_cu_w = r.p_cu;
  p.r_th_k_per_w = r.r_th;
  p.tau_th_s = r.tau;
  p.temperature_available = r.temperature;
  p.supply_nominal_v = r.supply;
  return p;
}

const std::vector<int> k_in_349 = {1, 2, 3, 4};
const std::vector<int> k_out_349 = {1, 2};
const std::vector<int> k_in_n23 = {1, 2, 3, 4, 5, 6, 7};
const std::vector<int> k_in_hybrid = {1, 2, 3, 4, 5, 6, 7, 8, 10};
const std::vector<int> k_out_4 = {1, 2, 3, 4};

ModelPreset mc349(bool ae) {
  ModelPreset m;
  m.name = ae ? "MC349_AE" : "MC349";
  m.base = Base::mc349;
  m.xdd_file = "MC349_ETH.xdd";
  m.ae_extras = ae;
  m.identity = ae ? identity("MC349_ETH_AE", "v50.01.10.00_AE", 50, "MC349", "MovingCap turnTRACK 349 Eth")
                  : identity("MC349_ETH_RE", "v50.00.10.00_RE", 50, "MC349", "MovingCap turnTRACK 349 Eth");
  m.plant =
      plant({0.30, 0.15, 2.0e-5, 1.0e-5, 0.006, 4500, 150, 0, std::nullopt, 0, 10, ae, 2, 40, 3.0, 600, false, 48});
  m.input_pins = k_in_349;
  m.output_pins = k_out_349;
  m.factory_values = {{{0x6075, 0}, 12000}, {{0x3401, 0x18}, 1000}};
  return m;
}

ModelPreset mcn23() {
  ModelPreset m;
  m.name = "MCN23";
  m.base = Base::mcn23;
  m.xdd_file = "MCN23_ETH.xdd";
  m.identity = identity("MCN23_ETH_AE", "v52.06.10.00_AE", 52, "MCN23", "MovingCap turnTRACK N23 Eth");
  m.plant =
      plant({1.8, 0.81, 4.8e-5, 5.0e-5, 0.03, 1000, 80, 65536, std::nullopt, 0, 10, true, 3, 30, 2.5, 900, true, 24});
  m.input_pins = k_in_n23;
  m.output_pins = k_out_4;
  m.combined_pins = k_out_4;
  m.factory_values = {{{0x6075, 0}, 4000}, {{0x3401, 0x18}, 100}};
  return m;
}

ModelPreset rabbit(bool short_track) {
  ModelPreset m;
  m.name = short_track ? "MCSHORT" : "MCFLAT";
  m.base = Base::mcflat;
  m.xdd_file = "MCFLAT_ETH.xdd";
  m.controller = Controller::rabbit;
  m.kind = Kind::linear;
  m.supported_modes = 0x21;
  if (short_track) {
    m.identity = identity("MCSHORT_ETH_SRABBIT", "v53.02.10.00_SRABBIT", 53, "MCSHORT", "MovingCap shortTRACK Eth");
    m.plant = plant({30, 10, 0.15, 5, 1.0, 2.0, 200, 5000, std::pair<std::int64_t, std::int64_t>{0, 46000}, 23000, 1,
                     true, 1, 20, 4.0, 300, true, 48});
  } else {
    m.identity = identity("MCFLAT_ETH_RABBIT", "v53.02.10.00_RABBIT", 53, "MCFLAT", "MovingCap flatTRACK Eth");
    m.plant = plant({100, 30, 0.70, 10, 2.0, 3.0, 200, 5000, std::pair<std::int64_t, std::int64_t>{0, 200000}, 100000,
                     1, true, 2, 50, 2.0, 600, true, 48});
  }
  m.plant.hw_enable_input = 10;
  m.input_pins = k_in_hybrid;
  m.output_pins = k_out_4;
  m.combined_pins = k_out_4;
  m.factory_values = {
      {{0x6075, 0}, short_track ? 4000 : 8000},
      {{0x3300, 0x04}, 0},
      {{0x3300, 0x05}, 0},
      {{0x3300, 0x07}, short_track ? 150 : 700},
      {{0x3301, 0x01}, 1},
      {{0x3301, 0x04}, 0},
      {{0x3301, 0x06}, 100},
      {{0x3301, 0x07}, 100},
      {{0x3301, 0x08}, 100},
      {{0x3301, 0x0E}, 0},
      {{0x3301, 0x0F}, 0},
      {{0x60A4, 0}, 50000},
      {{0x6081, 0}, 100000},
      {{0x3401, 0x04}, 0},
  };
  return m;
}

ModelPreset mc6xx(std::string_view name) {
  ModelPreset m;
  m.name = std::string(name);
  m.base = Base::mc6xx;
  m.xdd_file = "MC6xx_ETH.xdd";
  m.plant.hw_enable_input = 10;
  m.input_pins = k_in_hybrid;
  m.output_pins = k_out_4;
  m.combined_pins = k_out_4;
  if (name == "PUSHTRACK") {
    m.identity = identity("PUSHTRACK_ETH_AE", "v54.01.10.00_AE", 54, "PUSHTRACK", "MovingCap pushTRACK Eth");
    m.plant = plant({0.6, 0.3, 5.0e-5, 5.0e-5, 0.02, 3000, 120, 65536,
                     std::pair<std::int64_t, std::int64_t>{0, 1310720}, 655360, 10, true, 3, 60, 2.0, 900, true, 48});
    m.factory_values = {{{0x6075, 0}, 8000}};
  } else {
    const std::string digits(name.substr(2));  // "632", "634", "636"
    m.identity = identity(std::string(name) + "_ETH_AE", "v54.01.10.00_AE", 54, std::string(name),
                          "MovingCap turnTRACK " + digits + " Eth");
    if (name == "MC632") {
      m.plant = plant(
          {0.6, 0.3, 4.0e-5, 2.0e-5, 0.012, 4000, 150, 65536, std::nullopt, 0, 10, true, 3, 60, 2.0, 900, true, 48});
      m.factory_values = {{{0x6075, 0}, 8000}};
    } else if (name == "MC634") {
      m.plant = plant(
          {1.0, 0.5, 7.0e-5, 3.0e-5, 0.02, 4000, 150, 65536, std::nullopt, 0, 10, true, 3, 80, 1.6, 900, true, 48});
      m.factory_values = {{{0x6075, 0}, 12000}};
    } else {
      m.plant = plant(
          {1.4, 0.7, 1.0e-4, 4.0e-5, 0.028, 4000, 150, 65536, std::nullopt, 0, 10, true, 4, 100, 1.3, 900, true, 48});
      m.factory_values = {{{0x6075, 0}, 16000}};
    }
  }
  m.plant.hw_enable_input = 10;
  return m;
}

}  // namespace

std::span<const std::string_view> preset_names() { return k_names; }

std::span<const std::string_view> all_preset_names() { return k_all_names; }

std::optional<ModelPreset> find_preset(std::string_view name) {
  if (name == "MC349") return mc349(false);
  if (name == "MC349_AE") return mc349(true);
  if (name == "MCN23") return mcn23();
  if (name == "MCFLAT") return rabbit(false);
  if (name == "MCSHORT") return rabbit(true);
  if (name == "MC632" || name == "MC634" || name == "MC636" || name == "PUSHTRACK") return mc6xx(name);
  return find_faulhaber_preset(name);
}

std::string_view to_string(Base b) {
  switch (b) {
    case Base::mc349: return "MC349";
    case Base::mc6xx: return "MC6xx";
    case Base::mcflat: return "MCFLAT";
    case Base::mcn23: return "MCN23";
    case Base::faulhaber: return "FAULHABER";
  }
  return "?";
}

std::string_view to_string(Family f) { return f == Family::faulhaber ? "faulhaber" : "movingcap"; }

}  // namespace mcemu::model
