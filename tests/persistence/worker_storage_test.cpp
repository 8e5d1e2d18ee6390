// The persistence worker thread (persistence/worker_storage.hpp, persistence.md §12) with real
// files in a temporary directory: writes run in request order on the worker, completions arrive on
// the loop thread, drain() and the destructor finish what is queued. The ThreadSanitizer build of
// tools/dev test runs these (the worker is the process's only other thread).
#include "persistence/worker_storage.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <boost/asio/executor_work_guard.hpp>
#include <fstream>
#include <sstream>
#include <thread>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::persistence {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  TempDir()
      : path(fs::temp_directory_path() / ("mcemu-worker-" + std::to_string(::getpid()) + "-" + std::to_string(n++))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
  static inline int n = 0;
};

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs the loop until `count` completions have arrived (bounded by a generous deadline).
void run_until(boost::asio::io_context& io, const int& done, int count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (done < count && std::chrono::steady_clock::now() < deadline) {
    io.restart();
    io.run_one_for(std::chrono::milliseconds(100));
  }
}

TEST(WorkerStorage, WritesRunInOrderAndCompleteOnTheLoopThread) {
  TempDir dir;
  boost::asio::io_context io;
  WorkerStorage storage(io, dir.path / "drive-1.json", {});
  const auto loop_thread = std::this_thread::get_id();
  std::vector<int> order;
  int done = 0;
  for (int i = 0; i < 50; ++i) {
    storage.write_state("contents " + std::to_string(i), [&, i](std::optional<std::string> error) {
      EXPECT_FALSE(error) << *error;
      EXPECT_EQ(std::this_thread::get_id(), loop_thread);
      order.push_back(i);
      ++done;
    });
  }
  run_until(io, done, 50);
  ASSERT_EQ(done, 50);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(order[static_cast<std::size_t>(i)], i);
  EXPECT_EQ(read(dir.path / "drive-1.json"), "contents 49");
  EXPECT_FALSE(fs::exists(dir.path / "drive-1.json.tmp"));
}

TEST(WorkerStorage, DrainWaitsForTheQueueAndAFailureIsReported) {
  TempDir dir;
  std::ofstream(dir.path / "not-a-dir") << "x";
  boost::asio::io_context io;
  WorkerStorage storage(io, dir.path / "drive-1.json", {});
  std::optional<std::string> failure;
  int done = 0;
  storage.write_file(dir.path / "drive-1.plant.json", "plant", [&](std::optional<std::string> e) {
    EXPECT_FALSE(e);
    ++done;
  });
  storage.write_file(dir.path / "not-a-dir" / "drive-1.json", "x", [&](std::optional<std::string> e) {
    failure = std::move(e);
    ++done;
  });
  storage.drain();  // both files are done (the completions are still queued on the loop)
  EXPECT_EQ(read(dir.path / "drive-1.plant.json"), "plant");
  EXPECT_EQ(done, 0);
  run_until(io, done, 2);
  ASSERT_TRUE(failure);
  EXPECT_NE(failure->find("not-a-dir"), std::string::npos) << *failure;
}

TEST(WorkerStorage, DestructorFinishesQueuedWrites) {
  TempDir dir;
  boost::asio::io_context io;
  {
    WorkerStorage storage(io, dir.path / "drive-1.json", {});
    for (int i = 0; i < 20; ++i) storage.write_state(std::string(10000, static_cast<char>('a' + i)), {});
  }
  EXPECT_EQ(read(dir.path / "drive-1.json"), std::string(10000, 't'));
}

TEST(WorkerStorage, StoreThroughTheServiceCompletesTheOdWrite) {
  TempDir dir;
  boost::asio::io_context io;
  const auto preset = *model::find_preset("MC349");
  od::ObjectDictionary od(preset);
  WorkerStorage storage(io, dir.path / "drive-1.json", {});
  Service service(od, preset.name, "test", [f = snapshot(od)] { return f; }, std::nullopt, storage, {});
  int done = 0;
  std::vector<od::AbortCode> codes;
  for (int i = 0; i < 5; ++i) {
    ASSERT_EQ(od.write(0x6083, 0, od::Value{std::int64_t{1000 + i}}, od::Origin::sdo), od::AbortCode::none);
    const auto r = od.write(0x1010, 1, od::Value{k_save}, od::Origin::sdo, [&](od::AbortCode c) {
      codes.push_back(c);
      ++done;
    });
    EXPECT_EQ(r, od::AbortCode::pending);
  }
  run_until(io, done, 5);
  EXPECT_EQ(codes, std::vector<od::AbortCode>(5, od::AbortCode::none));
  ASSERT_TRUE(service.on_file());
  const auto parsed = parse(read(dir.path / "drive-1.json"), preset.name, od);
  ASSERT_TRUE(std::holds_alternative<ParsedFile>(parsed));
  EXPECT_NE(read(dir.path / "drive-1.json").find("1004"), std::string::npos);
}

}  // namespace
}  // namespace mcemu::persistence
