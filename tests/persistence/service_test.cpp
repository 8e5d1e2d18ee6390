// Store/Restore through the OD write hooks with a fake storage (persistence.md §3, §4, §12).
#include "persistence/service.hpp"

#include <gtest/gtest.h>

#include <deque>

#include "drive/model/model_preset.hpp"

namespace mcemu::persistence {
namespace {

using od::AbortCode;
using od::Origin;
using od::Value;

class FakeStorage final : public Storage {
 public:
  void write_state(std::string contents, Completion done) override {
    queue.push_back({std::move(contents), std::move(done)});
  }
  // Completes the oldest write (the worker runs jobs in order).
  void complete(std::optional<std::string> error = std::nullopt) {
    auto job = std::move(queue.front());
    queue.pop_front();
    if (!error) files.push_back(job.first);
    job.second(error);
  }
  std::deque<std::pair<std::string, Completion>> queue;
  std::vector<std::string> files;
};

struct Fixture {
  explicit Fixture(std::string_view model = "MC349", std::optional<Image> on_file = std::nullopt)
      : preset(*model::find_preset(model)), od(preset) {
    ServiceHooks hooks;
    hooks.operation_enabled = [this] { return enabled; };
    hooks.after_restore = [this] { ++restores; };
    hooks.reset_script = [this] { ++script_resets; };
    hooks.home_offset_inc = [] { return std::int64_t{4242}; };
    service = std::make_unique<Service>(
        od, preset.name, "0.1.0", [f = snapshot(od)] { return f; }, std::move(on_file), storage, hooks);
  }
  AbortCode write(std::uint16_t i, std::uint8_t s, std::int64_t v, std::vector<AbortCode>* results = nullptr) {
    return od.write(i, s, Value{v}, Origin::sdo, [results](AbortCode c) {
      if (results) results->push_back(c);
    });
  }
  std::int64_t n(std::uint16_t i, std::uint8_t s) { return *od.read_number(i, s); }
  ParsedFile last_file() {
    auto r = parse(storage.files.back(), preset.name, od);
    return std::get<ParsedFile>(r);
  }
  std::int64_t file_value(std::uint16_t i, std::uint8_t s) {
    for (const auto& sv : last_file().image.objects) {
      if (sv.index == i && sv.sub == s) return std::get<std::int64_t>(sv.value);
    }
    throw std::runtime_error("not in file");
  }

  model::ModelPreset preset;
  od::ObjectDictionary od;
  FakeStorage storage;
  std::unique_ptr<Service> service;
  bool enabled = false;
  int restores = 0;
  int script_resets = 0;
};

TEST(Store, SignatureAndPendingCompletion) {
  Fixture f;
  std::vector<AbortCode> results;
  EXPECT_EQ(f.write(0x1010, 1, 0x12345678, &results), AbortCode::cannot_store);
  EXPECT_TRUE(f.storage.queue.empty());
  f.write(0x6083, 0, 2500);
  EXPECT_EQ(f.write(0x1010, 1, k_save, &results), AbortCode::pending);
  EXPECT_TRUE(results.empty()) << "no answer before the file is durable";
  f.storage.complete();
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0], AbortCode::none);
  EXPECT_EQ(f.file_value(0x6083, 0), 2500);
  EXPECT_EQ(f.last_file().image.home_offset_inc, 4242);
  EXPECT_EQ(f.n(0x1010, 1), 1) << "the written value is not kept";
  EXPECT_EQ(f.n(0x5006, 5), 1);
  EXPECT_EQ(f.n(0x5006, 1), 1);
  EXPECT_EQ(f.file_value(0x5006, 5), 1);
}

TEST(Store, AllThreeSubIndicesStoreEverything) {
  for (std::uint8_t sub : {1, 2, 3}) {
    Fixture f;
    f.write(0x6083, 0, 3000 + sub);
    EXPECT_EQ(f.write(0x1010, sub, k_save), AbortCode::pending);
    f.storage.complete();
    EXPECT_EQ(f.file_value(0x6083, 0), 3000 + sub);
  }
}

TEST(Store, FailureAnswersHardwareErrorAndChangesNothing) {
  Fixture f;
  std::vector<AbortCode> results;
  f.write(0x1010, 1, k_save, &results);
  f.storage.complete("cannot create /x: Permission denied");
  EXPECT_EQ(results, std::vector<AbortCode>{AbortCode::hardware_error});
  EXPECT_EQ(f.n(0x5006, 5), 0);
  EXPECT_EQ(f.n(0x5006, 1), 0);
  EXPECT_EQ(f.n(0x5006, 4), 1);
}

TEST(Store, RequestsRunInOrderWithTheirOwnSnapshots) {
  Fixture f;
  std::vector<AbortCode> results;
  for (int i = 0; i < 10; ++i) {
    f.write(0x6083, 0, 100 + i);
    f.write(0x1010, 1, k_save, &results);
  }
  EXPECT_EQ(f.storage.queue.size(), 10u);
  for (int i = 0; i < 10; ++i) {
    f.storage.complete();
    EXPECT_EQ(f.file_value(0x6083, 0), 100 + i);
  }
  EXPECT_EQ(results.size(), 10u);
  EXPECT_EQ(f.n(0x5006, 5), 10);
}

// A completion that arrives after the service is gone (the drive shut down and was destroyed while
// its file was written) is dropped: it answers nobody and touches nothing.
TEST(Store, ACompletionAfterTheServiceIsGoneIsDropped) {
  Fixture f;
  std::vector<AbortCode> results;
  EXPECT_EQ(f.write(0x1010, 1, k_save, &results), AbortCode::pending);
  f.service.reset();
  f.storage.complete();
  EXPECT_TRUE(results.empty());
  EXPECT_EQ(f.n(0x5006, 5), 0) << "the counter of the gone service is not written";
}

TEST(MotorStore, StoresOnlyTheMotorGroup) {
  Fixture f("MCFLAT");
  f.write(0x3300, 7, 812);
  f.write(0x6083, 0, 7777);
  EXPECT_EQ(f.n(0x3010, 2), 0);
  EXPECT_EQ(f.write(0x3010, 1, 0x1), AbortCode::cannot_store);
  EXPECT_EQ(f.write(0x3010, 1, k_save), AbortCode::pending);
  f.storage.complete();
  EXPECT_EQ(f.file_value(0x3300, 7), 812);
  EXPECT_EQ(f.file_value(0x6083, 0), 1000) << "the parameters group keeps what is on file (factory)";
  EXPECT_EQ(f.n(0x3010, 2), 1);
}

TEST(Restore, RefusedInOperationEnabledAndWithWrongSignature) {
  Fixture f;
  f.enabled = true;
  EXPECT_EQ(f.write(0x1011, 1, k_load), AbortCode::device_state);
  f.enabled = false;
  EXPECT_EQ(f.write(0x1011, 1, k_save), AbortCode::cannot_store);
  EXPECT_TRUE(f.storage.queue.empty());
}

TEST(Restore, FactoryValuesAfterDurableFileSurvivorsKept) {
  Fixture f("MCFLAT");
  f.write(0x5007, 4, 77);
  f.write(0x3300, 7, 812);
  f.write(0x3301, 4, 500);
  f.write(0x6083, 0, 4444);
  f.write(0x3500, 4, 1);
  f.write(0x1010, 1, k_save);
  f.storage.complete();
  std::vector<AbortCode> results;
  EXPECT_EQ(f.write(0x1011, 1, k_load, &results), AbortCode::pending);
  EXPECT_EQ(f.n(0x6083, 0), 4444) << "RAM changes only when the file is durable";
  f.storage.complete();
  EXPECT_EQ(results, std::vector<AbortCode>{AbortCode::none});
  EXPECT_EQ(f.n(0x6083, 0), 1000);
  EXPECT_EQ(f.n(0x3301, 4), 0);
  EXPECT_EQ(f.n(0x3500, 4), 0);
  EXPECT_EQ(f.n(0x3300, 7), 812) << "motor group survives";
  EXPECT_EQ(f.n(0x5007, 4), 77) << "network identity survives";
  EXPECT_EQ(f.restores, 1);
  EXPECT_EQ(f.script_resets, 1);
  const auto file = f.last_file();
  EXPECT_EQ(f.file_value(0x6083, 0), 1000);
  EXPECT_EQ(f.file_value(0x3300, 7), 812);
  EXPECT_EQ(f.file_value(0x5007, 4), 77);
  EXPECT_EQ(file.image.home_offset_inc, 0);
  EXPECT_FALSE(file.image.autostart);
  EXPECT_TRUE(file.image.script.is_null());
}

TEST(Restore, FailedWriteChangesNothing) {
  Fixture f;
  f.write(0x6083, 0, 4444);
  std::vector<AbortCode> results;
  f.write(0x1011, 1, k_load, &results);
  f.storage.complete("disk full");
  EXPECT_EQ(results, std::vector<AbortCode>{AbortCode::hardware_error});
  EXPECT_EQ(f.n(0x6083, 0), 4444);
  EXPECT_EQ(f.restores, 0);
}

TEST(Restore, VolatileEntriesAreNotTouched) {
  Fixture f;
  f.write(0x6060, 0, 1);
  f.write(0x1011, 1, k_load);
  f.storage.complete();
  EXPECT_EQ(f.n(0x6060, 0), 1);
}

}  // namespace
}  // namespace mcemu::persistence
