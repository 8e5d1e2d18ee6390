// Trace JSON (web.md §8.6) and the two exports: the candump log of the slcan channel and the
// timestamped text log. The candump log is also read back with python-can's can.LogReader when
// Debian's python3-can is installed.
#include "web/api/trace_export.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tests/web/api_fixture.hpp"

namespace mcemu::web::api {
namespace {

using nlohmann::json;

trace::Event slcan_event(std::string text, trace::Dir dir = trace::Dir::tx,
                         std::int64_t wall_ms = 1700000000123) {  // 2023-11-14T22:13:20.123Z
  trace::Event e;
  e.channel = trace::Channel::slcan;
  e.dir = dir;
  e.text = std::move(text);
  e.wall_ms = wall_ms;
  e.time_ms = 5123;
  e.conn = 1;
  return e;
}

TEST(SlcanFrames, LinesToCandumpFrames) {
  struct Case {
    const char* line;
    const char* frame;  // nullptr = not a frame
  };
  for (const auto& c :
       {Case{"t1238DEADBEEF00112233\r", "123#DEADBEEF00112233"},
        Case{"t0B282132050000000000\r", "0B2#2132050000000000"}, Case{"t7321FF", "732#FF"}, Case{"t1230\r", "123#"},
        Case{"r7320\r", "732#R"}, Case{"r7324\r", "732#R4"}, Case{"T123456784AABBCCDD\r", "12345678#AABBCCDD"},
        Case{"R1FFFFFFF0\r", "1FFFFFFF#R"}, Case{"t12311A2B3C\r", "123#1A"},  // timestamp
        Case{"z\r", nullptr}, Case{"\a", nullptr}, Case{"O\r", nullptr}, Case{"t12\r", nullptr},
        Case{"t1239\r", nullptr}, Case{"tXYZ0\r", nullptr}, Case{"", nullptr}, Case{"V1010\r", nullptr}}) {
    const auto f = frame_of_slcan_line(c.line);
    if (!c.frame) {
      EXPECT_FALSE(f) << c.line;
    } else {
      ASSERT_TRUE(f) << c.line;
      EXPECT_EQ(candump_frame(*f), c.frame) << c.line;
    }
  }
}

TEST(CandumpLog, FramesOnlyWithWallTime) {
  std::vector<trace::Event> events{
      slcan_event("t0B282132050000000000\r"), slcan_event("z\r"), slcan_event("connect", trace::Dir::event),
      slcan_event("t6328400010000\r", trace::Dir::rx), slcan_event("t7321FF\r", trace::Dir::tx, -1)};
  events[3].text = "t6328400010000\r";  // 8 data bytes missing → not a frame
  trace::Event other = slcan_event("t1230\r");
  other.channel = trace::Channel::refgo;
  events.push_back(other);
  EXPECT_EQ(candump_log(events),
            "(1700000000.123000) can0 0B2#2132050000000000\n"
            "(5.123000) can0 732#FF\n");
}

TEST(TextLog, DocklightLikeControlBytes) {
  trace::Event e;
  e.channel = trace::Channel::refgo;
  e.dir = trace::Dir::rx;
  e.conn = 3;
  e.time_ms = 53021;
  e.wall_ms = 1768472102123;  // 2026-01-15T10:15:02.123Z
  e.text = "OR6041,0,h\r";
  trace::Event u;
  u.channel = trace::Channel::udp;
  u.dir = trace::Dir::tx;
  u.time_ms = 53022;
  u.text = std::string("Hello\r\n\x01\t\x7F", 10);
  u.flags.ignored = true;
  const std::vector<trace::Event> events{e, u};
  EXPECT_EQ(text_log(events),
            "2026-01-15T10:15:02.123Z 53021 refgo rx #3 OR6041,0,h<CR>\n"
            "- 53022 udp tx - Hello<CR><LF><01><TAB><7F> [ignored]\n");
}

TEST(TraceJson, EventFieldsAndFlags) {
  trace::Event e = slcan_event("t1230\r", trace::Dir::rx);
  e.seq = 7;
  e.peer = "127.0.0.1:5000";
  e.flags.overlong = true;
  const json j = event_json(e);
  EXPECT_EQ(j, (json{{"seq", 7},
                     {"timeMs", 5123},
                     {"wall", "2023-11-14T22:13:20.123Z"},
                     {"channel", "slcan"},
                     {"dir", "rx"},
                     {"conn", 1},
                     {"peer", "127.0.0.1:5000"},
                     {"text", "t1230\r"},
                     {"overlong", true}}));
  trace::Event bare;
  const json b = event_json(bare);
  EXPECT_EQ(b["conn"], nullptr);
  EXPECT_EQ(b["peer"], nullptr);
  EXPECT_FALSE(b.contains("overlong"));
}

// ---- through the router ----------------------------------------------------------------------

TEST(TraceEndpoints, QueryParametersAndErrors) {
  testing::ApiFixture f;
  for (int i = 0; i < 5; ++i) f.ring.record(trace::Channel::refgo, trace::Dir::rx, "TP\r", 2, "127.0.0.1:1");
  f.ring.record(trace::Channel::udp, trace::Dir::tx, "x\r\n");
  auto j = f.get("/api/v1/trace");
  EXPECT_EQ(j["events"].size(), 6u);
  EXPECT_EQ(j["nextSeq"], 7);
  EXPECT_EQ(j["dropped"], 0);
  j = f.get("/api/v1/trace?channels=udp");
  ASSERT_EQ(j["events"].size(), 1u);
  EXPECT_EQ(j["events"][0]["text"], "x\r\n");
  j = f.get("/api/v1/trace?since=3&limit=2&channels=refgo%2Cudp");
  ASSERT_EQ(j["events"].size(), 2u);
  EXPECT_EQ(j["events"][0]["seq"], 3);
  EXPECT_EQ(j["nextSeq"], 5);
  for (const char* bad : {"?limit=0", "?limit=10001", "?limit=x", "?since=-1", "?since=1.5", "?channels=nope",
                          "?channels=", "?channels=refgo,", "?foo=1", "?since=1&since=2", "?since=%zz"}) {
    const auto r = f.call("GET", std::string("/api/v1/trace") + bad);
    EXPECT_EQ(r.status, 400) << bad;
    EXPECT_TRUE(f.json_of(r).contains("error")) << bad;
  }
  EXPECT_EQ(f.call("GET", "/api/v1/trace?limit=10000").status, 200);
}

// web.md §8.6: requests the pages repeat on a timer are marked "polling" and left out with
// excludePolling=1 (the Emulator page's trace view asks for that).
TEST(TraceEndpoints, ExcludePolling) {
  testing::ApiFixture f;
  trace::Flags polling;
  polling.polling = true;
  f.ring.record(trace::Channel::http, trace::Dir::rx, "GET /api/v1/io", 3, "127.0.0.1:1", polling);
  f.ring.record(trace::Channel::http, trace::Dir::tx, "200", 3, "127.0.0.1:1", polling);
  f.ring.record(trace::Channel::http, trace::Dir::rx, "POST /api/v1/store", 3, "127.0.0.1:1");
  auto j = f.get("/api/v1/trace?channels=http");
  ASSERT_EQ(j["events"].size(), 3u);
  EXPECT_EQ(j["events"][0]["polling"], true);
  EXPECT_FALSE(j["events"][2].contains("polling"));
  for (const char* on : {"1", "true"}) {
    j = f.get(std::string("/api/v1/trace?channels=http&excludePolling=") + on);
    ASSERT_EQ(j["events"].size(), 1u) << on;
    EXPECT_EQ(j["events"][0]["text"], "POST /api/v1/store");
  }
  EXPECT_EQ(f.get("/api/v1/trace?excludePolling=0")["events"].size(), 3u);
  EXPECT_EQ(f.call("GET", "/api/v1/trace?excludePolling=yes").status, 400);
  auto r = f.call("GET", "/api/v1/trace/text?channels=http");
  EXPECT_NE(r.body.find("GET /api/v1/io [polling]"), std::string::npos) << r.body;
  r = f.call("GET", "/api/v1/trace/text?channels=http&excludePolling=1");
  EXPECT_EQ(r.body, "2026-01-15T10:15:02.123Z 0 http rx #3 POST /api/v1/store\n");
}

TEST(TraceEndpoints, ExportsAsText) {
  testing::ApiFixture f;
  f.ring.record(trace::Channel::slcan, trace::Dir::tx, "t0B282132050000000000\r", 1);
  f.ring.record(trace::Channel::slcan, trace::Dir::tx, "t0B282132050000000000\r", 2);
  f.ring.record(trace::Channel::refgo, trace::Dir::rx, "TP\r", 4);
  f.ring.record(trace::Channel::api, trace::Dir::event, "store ok");
  auto r = f.call("GET", "/api/v1/trace/candump");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "text/plain; charset=utf-8");
  EXPECT_EQ(r.body, "(1768472102.123000) can0 0B2#2132050000000000\n(1768472102.123000) can0 0B2#2132050000000000\n");
  r = f.call("GET", "/api/v1/trace/candump?conn=2");
  EXPECT_EQ(r.body, "(1768472102.123000) can0 0B2#2132050000000000\n") << "one session's view";
  r = f.call("GET", "/api/v1/trace/text");
  EXPECT_EQ(r.body, "2026-01-15T10:15:02.123Z 0 refgo rx #4 TP<CR>\n") << "default channels refgo,udp";
  r = f.call("GET", "/api/v1/trace/text?channels=api");
  EXPECT_EQ(r.body, "2026-01-15T10:15:02.123Z 0 api event - store ok\n");
  EXPECT_EQ(f.call("GET", "/api/v1/trace/candump?conn=0").status, 400);
  EXPECT_EQ(f.call("GET", "/api/v1/trace/text?channels=bogus").status, 400);
}

TEST(TraceEndpoints, WithoutARingThey503) {
  testing::ApiFixture f;
  f.services.trace = nullptr;
  f.make_router();
  for (const char* p : {"/api/v1/trace", "/api/v1/trace/candump", "/api/v1/trace/text"}) {
    const auto r = f.call("GET", p);
    EXPECT_EQ(r.status, 503) << p;
    EXPECT_EQ(f.json_of(r)["error"]["code"], "unavailable");
  }
}

// python-can (Debian python3-can) reads the export exactly as a candump -l file.
TEST(CandumpLog, ReadByPythonCanLogReader) {
  if (std::system("/usr/bin/python3 -c 'import can' >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3-can not installed";
  }
  std::vector<trace::Event> events{slcan_event("t0B282132050000000000\r"), slcan_event("r7324\r", trace::Dir::rx),
                                   slcan_event("T123456784AABBCCDD\r"), slcan_event("t1230\r")};
  const auto dir = std::filesystem::temp_directory_path() / ("mcemu-candump-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto log = dir / "trace.log";
  const auto script = dir / "read.py";
  std::ofstream(log) << candump_log(events);
  std::ofstream(script) << "import can, sys\n"
                           "out = []\n"
                           "for m in can.LogReader(sys.argv[1]):\n"
                           "    d = '' if m.is_remote_frame else bytes(m.data).hex().upper()\n"
                           "    out.append('%.6f %X %d %d %d %s' % (m.timestamp, m.arbitration_id, m.is_extended_id,"
                           " m.is_remote_frame, m.dlc, d))\n"
                           "print('|'.join(out))\n";
  const std::string out_file = (dir / "out.txt").string();
  const std::string cmd = "/usr/bin/python3 " + script.string() + " " + log.string() + " > " + out_file + " 2>" +
                          (dir / "err.txt").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(out_file);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "1700000000.123000 B2 0 0 8 2132050000000000|1700000000.123000 732 0 1 4 |"
            "1700000000.123000 12345678 1 0 4 AABBCCDD|1700000000.123000 123 0 0 0 ");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mcemu::web::api
