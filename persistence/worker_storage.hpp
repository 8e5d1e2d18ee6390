// The persistence worker thread (persistence.md §12): file writes run here, strictly in request
// order; each completion is posted back to the event loop. The only thread of the process besides
// the loop (and the script engine, later).
#pragma once

#include <boost/asio/io_context.hpp>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>

#include "persistence/atomic_file.hpp"
#include "persistence/service.hpp"

namespace mcemu::persistence {

class WorkerStorage final : public Storage {
 public:
  WorkerStorage(boost::asio::io_context& io, std::filesystem::path state_file, WriteOptions options);
  ~WorkerStorage() override;  // finishes the queued jobs, then joins
  WorkerStorage(const WorkerStorage&) = delete;
  WorkerStorage& operator=(const WorkerStorage&) = delete;

  void write_state(std::string contents, Completion done) override;
  // Any file (the plant state); same atomic procedure, same queue.
  void write_file(std::filesystem::path path, std::string contents, Completion done);
  // Blocks until every queued job has run (clean shutdown).
  void drain();

 private:
  struct Job {
    std::filesystem::path path;
    std::string contents;
    Completion done;
  };
  void run();

  boost::asio::io_context& io_;
  std::filesystem::path state_file_;
  WriteOptions options_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::condition_variable idle_cv_;
  std::deque<Job> jobs_;
  bool busy_ = false;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace mcemu::persistence
