// The drives of one process (server/fleet.hpp): --drives N address counting, --port-step, --fleet
// entries, and every refusal naming the drive and the key.
#include "server/fleet.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

namespace mcemu::server {
namespace {

using json = nlohmann::json;

Settings with_drives(std::vector<std::string> args) { return parse_command_line(args); }

json factory_ip(const Settings& s) {
  json out = json::array();
  for (int i = 1; i <= 4; ++i) {
    const auto key = "5007.0" + std::to_string(i);
    out.push_back(s.config.contains("objects") && s.config["objects"].contains(key) ? s.config["objects"][key]
                                                                                    : json(nullptr));
  }
  return out;
}

TEST(Fleet, OneDriveIsTheProcessSettings) {
  const auto drives = expand_fleet(with_drives({"--refgo-port", "0"}));
  ASSERT_EQ(drives.size(), 1U);
  EXPECT_EQ(drives[0].bind, "127.0.0.1");
  EXPECT_EQ(drives[0].ip, "192.168.2.150");
  EXPECT_EQ(drives[0].refgo_port, 0);
  EXPECT_FALSE(drives[0].config.contains("objects"));
}

TEST(Fleet, DrivesCountBindAndIp) {
  const auto drives = expand_fleet(with_drives({"--drives", "3"}));
  ASSERT_EQ(drives.size(), 3U);
  const std::vector<std::string> binds = {"127.0.0.1", "127.0.0.2", "127.0.0.3"};
  const std::vector<std::string> ips = {"192.168.2.150", "192.168.2.151", "192.168.2.152"};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(drives[i].bind, binds[i]);
    EXPECT_EQ(drives[i].ip, ips[i]);
    EXPECT_EQ(drives[i].refgo_port, 10001);  // the usual four ports on every address
    EXPECT_EQ(drives[i].http_port, 80);
    EXPECT_EQ(drives[i].drives, 1U);
  }
  // Without an explicit --ip the counted address is the drive's factory 5007h (a stored one wins).
  EXPECT_FALSE(drives[1].ip_explicit);
  EXPECT_EQ(factory_ip(drives[1]), json::parse("[192,168,2,151]"));
  EXPECT_EQ(factory_ip(drives[2]), json::parse("[192,168,2,152]"));
  EXPECT_FALSE(drives[0].config.contains("objects"));
}

TEST(Fleet, AddressesAreCountedAs32BitNumbers) {
  struct Case {
    std::string address;
    std::uint32_t offset;
    std::string expected;
  };
  for (const auto& c : std::vector<Case>{{"127.0.0.1", 0, "127.0.0.1"},
                                         {"127.0.0.255", 1, "127.0.1.0"},
                                         {"127.0.0.1", 255, "127.0.1.0"},
                                         {"10.255.255.255", 1, "11.0.0.0"},
                                         {"255.255.255.254", 1, "255.255.255.255"}}) {
    EXPECT_EQ(add_to_ipv4(c.address, c.offset, "--bind"), c.expected) << c.address << " + " << c.offset;
  }
  EXPECT_THROW(add_to_ipv4("255.255.255.255", 1, "--bind"), UsageError);
  const auto drives = expand_fleet(with_drives({"--drives", "300", "--bind", "127.0.0.250"}));
  EXPECT_EQ(drives[5].bind, "127.0.0.255");
  EXPECT_EQ(drives[6].bind, "127.0.1.0");
  EXPECT_EQ(drives[299].bind, "127.0.2.37");  // 250 + 299 = 2·256 + 37
}

TEST(Fleet, ExplicitIpIsCountedAndWins) {
  const auto drives = expand_fleet(with_drives({"--drives", "2", "--ip", "10.0.0.255"}));
  EXPECT_EQ(drives[1].ip, "10.0.1.0");
  EXPECT_TRUE(drives[1].ip_explicit);
  EXPECT_FALSE(drives[1].config.contains("objects"));
}

TEST(Fleet, PortStepKeepsTheAddress) {
  const auto drives = expand_fleet(with_drives(
      {"--drives", "3", "--port-step", "10", "--refgo-port", "20001", "--slcan-port", "0", "--bind", "0.0.0.0"}));
  ASSERT_EQ(drives.size(), 3U);
  EXPECT_EQ(drives[2].bind, "0.0.0.0");
  EXPECT_EQ(drives[2].refgo_port, 20021);
  EXPECT_EQ(drives[2].slcan_port, 0);  // 0 = any free port, for every drive
  EXPECT_EQ(drives[2].http_port, 100);
  EXPECT_EQ(drives[2].udp_port, 15019);
  EXPECT_EQ(drives[2].ip, "192.168.2.152");
}

TEST(Fleet, Refusals) {
  const std::vector<std::vector<std::string>> bad = {
      {"--drives", "2", "--bind", "0.0.0.0"},                              // wildcard cannot be counted
      {"--drives", "2", "--bind", "::1"},                                  // IPv6 cannot be counted
      {"--drives", "2", "--bind", "255.255.255.255"},                      // past the last address
      {"--drives", "2", "--ip", "255.255.255.255"},                        // reported address past the last
      {"--drives", "3", "--port-step", "40000", "--refgo-port", "30000"},  // port past 65535
  };
  for (const auto& args : bad) {
    EXPECT_THROW(expand_fleet(with_drives(args)), UsageError) << args[2] << " " << args[3];
  }
  EXPECT_THROW(parse_command_line({"--drives", "0"}), UsageError);
  EXPECT_THROW(parse_command_line({"--drives", "5000"}), UsageError);
  EXPECT_THROW(parse_command_line({"--port-step", "0"}), UsageError);
}

Settings with_fleet(const json& fleet, std::vector<std::string> more = {}) {
  // one file per test and process: ctest -j runs the tests of this file side by side
  const std::string path = ::testing::TempDir() + "fleet_test_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                           std::to_string(::getpid()) + ".json";
  std::ofstream(path) << fleet.dump();
  std::vector<std::string> args = {"--fleet", path};
  args.insert(args.end(), more.begin(), more.end());
  return parse_command_line(args);
}

TEST(Fleet, FleetFileMixedModels) {
  const auto drives = expand_fleet(with_fleet(json::parse(R"([{"model": "MC349", "ip": "10.0.0.10"},
                      {"model": "MCFLAT", "bind": "127.0.0.7", "refgo_port": 0, "plant": {"load_kg": 2}},
                      {"model": "MCFLAT", "objects": {"6083.00": 2000}}])"),
                                              {"--http-port", "8080"}));
  ASSERT_EQ(drives.size(), 3U);
  EXPECT_EQ(drives[0].model, "MC349");
  EXPECT_EQ(drives[0].ip, "10.0.0.10");
  EXPECT_TRUE(drives[0].ip_explicit);
  EXPECT_EQ(drives[0].bind, "127.0.0.1");
  EXPECT_EQ(drives[1].model, "MCFLAT");
  EXPECT_EQ(drives[1].bind, "127.0.0.7");  // the entry's own address
  EXPECT_EQ(drives[1].refgo_port, 0);
  EXPECT_EQ(drives[1].http_port, 8080);  // from the command line
  EXPECT_EQ(drives[1].ip, "192.168.2.151");
  EXPECT_EQ(drives[1].config["plant"], json::parse(R"({"load_kg": 2})"));
  EXPECT_EQ(drives[2].bind, "127.0.0.3");  // counted like --drives
  EXPECT_EQ(drives[2].config["objects"]["6083.00"], 2000);
  EXPECT_EQ(factory_ip(drives[2]), json::parse("[192,168,2,152]"));
  EXPECT_FALSE(drives[0].config.contains("plant"));
}

// --dump-od/--dump-eds with a fleet (issue 23): --drive K names the drive; without it a process of
// more than one drive is refused, since the drives' dictionaries differ.
TEST(Fleet, DumpTargetIsTheDriveNamedByDrive) {
  const json fleet = json::parse(R"([{"model": "MC349"}, {"model": "MCFLAT", "objects": {"6083.00": 2000}}])");
  const auto second = dump_target(with_fleet(fleet, {"--dump-eds", "--drive", "2"}));
  EXPECT_EQ(second.model, "MCFLAT");
  EXPECT_EQ(second.config["objects"]["6083.00"], 2000);
  EXPECT_EQ(factory_ip(second), json::parse("[192,168,2,151]"));
  EXPECT_EQ(dump_target(with_fleet(fleet, {"--dump-od", "--drive=1"})).model, "MC349");
  EXPECT_EQ(dump_target(with_drives({"--dump-eds", "--model", "MCN23"})).model, "MCN23");
  EXPECT_EQ(dump_target(with_drives({"--dump-eds", "--drives", "3", "--drive", "3"})).ip, "192.168.2.152");
  const auto refused = [](const Settings& s) {
    try {
      dump_target(s);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refused(with_fleet(fleet, {"--dump-eds"})).find("choose the one to dump with --drive K (1 … 2)"),
            std::string::npos);
  EXPECT_NE(refused(with_drives({"--dump-od", "--drives", "2"})).find("--dump-od: this process has 2 drives"),
            std::string::npos);
  EXPECT_EQ(refused(with_fleet(fleet, {"--dump-eds", "--drive", "3"})), "--drive 3: this process has 2 drives");
  EXPECT_EQ(refused(with_drives({"--dump-eds", "--drive", "2"})), "--drive 2: this process has 1 drive");
  EXPECT_THROW(with_drives({"--drive", "1"}), UsageError);  // only with a dump
  EXPECT_THROW(with_drives({"--dump-eds", "--drive", "0"}), UsageError);
  EXPECT_THROW(with_drives({"--dump-eds", "--drive"}), UsageError);
  EXPECT_THROW(with_drives({"--dump-eds", "--drive", "x"}), UsageError);
  const std::string config = ::testing::TempDir() + "drive_key.json";
  std::ofstream(config) << R"({"drive": 1})";
  EXPECT_THROW(with_drives({"--dump-eds", "--config", config}), UsageError) << "not a config key";
}

TEST(Fleet, LintModePerDrive) {
  const auto drives = expand_fleet(
      with_fleet(json::parse(R"([{}, {"lint": "off"}, {"lint": {"mode": "strict"}}])"), {"--lint", "warn"}));
  ASSERT_EQ(drives.size(), 3U);
  EXPECT_EQ(drives[0].lint_mode, lint::Mode::warn);
  EXPECT_EQ(drives[1].lint_mode, lint::Mode::off);   // the entry's flag wins
  EXPECT_EQ(drives[2].lint_mode, lint::Mode::warn);  // --lint over the entry's section
  EXPECT_EQ(drives[2].config["lint"]["mode"], "strict");
}

TEST(Fleet, FleetSectionsReplaceTheConfigSection) {
  const std::string config = ::testing::TempDir() + "fleet_config.json";
  std::ofstream(config) << R"({"objects": {"6081.00": 100}, "model": "MCFLAT"})";
  const auto drives =
      expand_fleet(with_fleet(json::parse(R"([{}, {"objects": {"6083.00": 3000}}])"), {"--config", config}));
  EXPECT_EQ(drives[0].model, "MCFLAT");
  EXPECT_EQ(drives[0].config["objects"]["6081.00"], 100);
  EXPECT_EQ(drives[1].model, "MCFLAT");
  EXPECT_FALSE(drives[1].config["objects"].contains("6081.00"));
  EXPECT_EQ(drives[1].config["objects"]["6083.00"], 3000);
}

TEST(Fleet, FleetRefusals) {
  struct Case {
    std::string fleet;
    std::string message_part;
  };
  for (const auto& c : std::vector<Case>{{R"([{"drives": 2}])", "fleet entry 1: \"drives\""},
                                         {R"([{}, {"log_level": "debug"}])", "fleet entry 2"},
                                         {R"([{}, 5])", "fleet entry 2 must be a JSON object"},
                                         {R"([{"model": "NOPE"}])", "fleet entry 1: unknown model"},
                                         {R"([{"colour": "red"}])", "fleet entry 1: config: unknown key"}}) {
    try {
      expand_fleet(with_fleet(json::parse(c.fleet)));
      ADD_FAILURE() << c.fleet;
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(c.message_part), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(with_fleet(json::array()), UsageError);
  EXPECT_THROW(with_fleet(json::object()), UsageError);
  EXPECT_THROW(with_fleet(json::parse("[{}]"), {"--drives", "2"}), UsageError);
  EXPECT_THROW(parse_command_line({"--fleet", "/nonexistent/fleet.json"}), UsageError);
}

}  // namespace
}  // namespace mcemu::server
