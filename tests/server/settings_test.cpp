// Command line and config file of mcemu (spec README "Command line").
#include "server/settings.hpp"

#include <gtest/gtest.h>

namespace mcemu::server {
namespace {

using json = nlohmann::json;

TEST(CommandLine, Defaults) {
  const auto s = parse_command_line({});
  EXPECT_EQ(s.model, "MC349");
  EXPECT_EQ(s.bind, "127.0.0.1");
  EXPECT_EQ(s.refgo_port, 10001);
  EXPECT_EQ(s.slcan_port, 15001);
  EXPECT_EQ(s.http_port, 80);
  EXPECT_EQ(s.udp_port, 14999);
  EXPECT_EQ(s.ip, "192.168.2.150");
  EXPECT_FALSE(s.ip_explicit);
  EXPECT_EQ(s.state_dir, "./mcemu-state");
  EXPECT_EQ(s.log_level, "info");
  EXPECT_EQ(s.refgo_max_clients, 8u);
  EXPECT_EQ(s.slcan_max_clients, 8u);
  EXPECT_EQ(s.http_max_clients, 32u);
  EXPECT_EQ(s.idle_timeout.count(), 0) << "no idle timeout unless asked for (refgo.md §1.3)";
}

TEST(CommandLine, IdleTimeoutInSecondsFromFlagAndConfig) {
  EXPECT_EQ(parse_command_line({"--idle-timeout", "30"}).idle_timeout, std::chrono::seconds(30));
  EXPECT_EQ(parse_command_line({"--idle-timeout=0"}).idle_timeout, std::chrono::seconds(0));
  for (const char* key : {"idle-timeout", "idle_timeout"}) {
    Settings s;
    apply_config(s, json{{key, 90}}, {});
    EXPECT_EQ(s.idle_timeout, std::chrono::seconds(90)) << key;
  }
  Settings s;
  s.idle_timeout = std::chrono::seconds(5);
  apply_config(s, json{{"idle_timeout", 90}}, {"idle-timeout"});
  EXPECT_EQ(s.idle_timeout, std::chrono::seconds(5)) << "the command line wins";
}

TEST(CommandLine, AllFlagsBothSpellings) {
  const auto s = parse_command_line({"--model", "MCFLAT", "--bind=0.0.0.0", "--refgo-port", "0", "--slcan-port=1",
                                     "--http-port", "8080", "--udp-port", "65535", "--ip", "10.0.0.7", "--state-dir",
                                     "/tmp/x", "--log-level", "debug", "--max-clients", "100", "--dump-od"});
  EXPECT_EQ(s.model, "MCFLAT");
  EXPECT_EQ(s.bind, "0.0.0.0");
  EXPECT_EQ(s.refgo_port, 0);
  EXPECT_EQ(s.slcan_port, 1);
  EXPECT_EQ(s.http_port, 8080);
  EXPECT_EQ(s.udp_port, 65535);
  EXPECT_EQ(s.ip, "10.0.0.7");
  EXPECT_TRUE(s.ip_explicit);
  EXPECT_EQ(s.state_dir, "/tmp/x");
  EXPECT_EQ(s.log_level, "debug");
  EXPECT_EQ(s.refgo_max_clients, 100u);
  EXPECT_EQ(s.slcan_max_clients, 100u);
  EXPECT_EQ(s.http_max_clients, 100u);
  EXPECT_TRUE(s.dump_od);
  EXPECT_FALSE(s.dump_eds);
  EXPECT_TRUE(parse_command_line({"--dump-eds"}).dump_eds);
  EXPECT_THROW(parse_command_line({"--dump-eds=1"}), UsageError);
}

TEST(CommandLine, ApiTokenFile) {
  EXPECT_EQ(token_of_file_text("0123456789abcdef\n", "f"), "0123456789abcdef");
  EXPECT_EQ(token_of_file_text("  s3cr3t-t0ken-of-mcemu \r\nsecond line ignored\n", "f"), "s3cr3t-t0ken-of-mcemu");
  for (const char* bad : {"", "\n", "short\n", "0123456789 abcdef\n",
                          "0123456789\x01"
                          "abcdef"}) {
    try {
      token_of_file_text(bad, "/etc/mcemu/token");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("/etc/mcemu/token"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(parse_command_line({}).api_token.empty()) << "no token unless asked for";
  EXPECT_THROW(parse_command_line({"--api-token", "/nonexistent/token"}), UsageError);
  EXPECT_THROW(parse_command_line({"--api-token"}), UsageError);
}

TEST(CommandLine, UnsafeScriptsOnlyFromTheCommandLine) {
  EXPECT_FALSE(parse_command_line({}).unsafe_scripts) << "the sandbox is required by default";
  EXPECT_TRUE(parse_command_line({"--unsafe-scripts"}).unsafe_scripts);
  EXPECT_THROW(parse_command_line({"--unsafe-scripts=1"}), UsageError);
  for (const json& config : {json{{"unsafe-scripts", true}}, json{{"unsafe_scripts", true}}}) {
    Settings s;
    EXPECT_THROW(apply_config(s, config, {}), UsageError) << config.dump() << ": not from a config file";
  }
}

// --lint off|warn|strict (docs/lint.md §3); in a config file "lint" is the flag as a string and the
// section as an object.
TEST(CommandLine, LintModeFromFlagAndConfig) {
  EXPECT_FALSE(parse_command_line({}).lint_mode.has_value()) << "the config's lint.mode (default warn) decides";
  EXPECT_EQ(parse_command_line({"--lint", "strict"}).lint_mode, lint::Mode::strict);
  EXPECT_EQ(parse_command_line({"--lint=off"}).lint_mode, lint::Mode::off);
  try {
    parse_command_line({"--lint", "loud"});
    ADD_FAILURE() << "no error";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()), "invalid value 'loud' for --lint (off, warn, strict)");
  }
  Settings s;
  apply_config(s, json{{"lint", "warn"}}, {});
  EXPECT_EQ(s.lint_mode, lint::Mode::warn);
  Settings section;
  apply_config(section, json{{"lint", {{"mode", "off"}}}}, {});
  EXPECT_FALSE(section.lint_mode.has_value());  // the section is the bundle's to read
  EXPECT_EQ(section.config["lint"]["mode"], "off");
  Settings given;
  given.lint_mode = lint::Mode::strict;
  apply_config(given, json{{"lint", "off"}}, {"lint"});
  EXPECT_EQ(given.lint_mode, lint::Mode::strict);  // the command line wins
}

struct Bad {
  std::vector<std::string> args;
  std::string message_part;
};

class BadCommandLine : public ::testing::TestWithParam<Bad> {};

TEST_P(BadCommandLine, OneLineNamingTheProblem) {
  try {
    parse_command_line(GetParam().args);
    FAIL() << "accepted";
  } catch (const UsageError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(GetParam().message_part), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadCommandLine,
    ::testing::Values(Bad{{"--modle", "MC349"}, "unknown option --modle"}, Bad{{"--model", "mc349"}, "valid: MC349"},
                      Bad{{"--model"}, "needs a value"}, Bad{{"--refgo-port", "65536"}, "--refgo-port"},
                      Bad{{"--http-port", "-1"}, "--http-port"}, Bad{{"--udp-port", "12a"}, "--udp-port"},
                      Bad{{"--ip", "192.168.2"}, "--ip"}, Bad{{"--ip", "1.2.3.256"}, "--ip"},
                      Bad{{"--bind", "localhost"}, "--bind"}, Bad{{"--log-level", "verbose"}, "--log-level"},
                      Bad{{"--max-clients", "0"}, "--max-clients"}, Bad{{"stray"}, "unexpected argument"},
                      Bad{{"--help=1"}, "takes no value"}, Bad{{"--config", "/nonexistent/x.json"}, "cannot read"},
                      Bad{{"--idle-timeout", "-1"}, "--idle-timeout"}, Bad{{"--idle-timeout", "1.5"}, "--idle-timeout"},
                      Bad{{"--idle-timeout", "604801"}, "--idle-timeout"}));

TEST(Config, FlagsWithoutDashesAndCommandLineWins) {
  Settings s;
  apply_config(s,
               json{{"model", "MCN23"},
                    {"http-port", 8081},
                    {"state_dir", "/tmp/y"},
                    {"ip", "10.1.1.1"},
                    {"max-clients", 4},
                    {"slcan", {{"max_clients", 2}}},
                    {"http", {{"ws_max_clients", 120}}},
                    {"faulhaber", {{"max_clients", 3}}},
                    {"trace", {{"events", 1000}}},
                    {"objects", {{"6083.00", 2000}}}},
               {"model"});
  EXPECT_EQ(s.model, "MC349") << "the command line wins";
  EXPECT_EQ(s.http_port, 8081);
  EXPECT_EQ(s.state_dir, "/tmp/y");
  EXPECT_TRUE(s.ip_explicit) << "\"ip\" in the config counts as explicit";
  EXPECT_EQ(s.refgo_max_clients, 4u);
  EXPECT_EQ(s.slcan_max_clients, 2u) << "a per-service key overrides max-clients";
  EXPECT_EQ(s.http_max_clients, 4u);
  EXPECT_EQ(s.faulhaber_max_clients, 3u) << "the FAULHABER port's own key";
  EXPECT_EQ(s.ws_max_clients, 120u);
  EXPECT_EQ(Settings{}.ws_max_clients, 16u);
  EXPECT_EQ(s.config["objects"]["6083.00"], 2000);
  EXPECT_EQ(s.config["trace"]["events"], 1000) << "the drive's section (device/device.cpp)";
}

TEST(Config, InvalidValuesAreUsageErrors) {
  for (const json& bad :
       {json{{"modell", "x"}}, json{{"http_port", "eighty"}}, json{{"http_port", 70000}}, json{{"objects", 5}},
        json{{"model", "MC999"}}, json{{"slcan", {{"max_clients", 0}}}}, json{{"http", {{"ws_max_clients", 0}}}},
        json{{"faulhaber", {{"max_clients", 0}}}}, json{{"faulhaber", {{"max_clients", "two"}}}},
        json{{"http", {{"ws_max_clients", "many"}}}}, json{{"ip", true}}, json{{"trace", 1000}}, json::array()}) {
    Settings s;
    EXPECT_THROW(apply_config(s, bad, {}), UsageError) << bad.dump();
  }
}

}  // namespace
}  // namespace mcemu::server
