#include "persistence/worker_storage.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <chrono>

namespace mcemu::persistence {

WorkerStorage::WorkerStorage(boost::asio::io_context& io, std::filesystem::path state_file, WriteOptions options)
    : io_(io), state_file_(std::move(state_file)), options_(options), thread_([this] { run(); }) {}

WorkerStorage::~WorkerStorage() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void WorkerStorage::write_state(std::string contents, Completion done) {
  write_file(state_file_, std::move(contents), std::move(done));
}

void WorkerStorage::write_file(std::filesystem::path path, std::string contents, Completion done) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(Job{std::move(path), std::move(contents), std::move(done)});
  }
  cv_.notify_one();
}

void WorkerStorage::drain() {
  std::unique_lock lock(mutex_);
  idle_cv_.wait(lock, [this] { return jobs_.empty() && !busy_; });
}

void WorkerStorage::run() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;  // stopping and nothing left
      job = std::move(jobs_.front());
      jobs_.pop_front();
      busy_ = true;
    }
    const auto started = std::chrono::steady_clock::now();
    auto error = write_atomically(job.path, job.contents, options_);
    const auto took = std::chrono::steady_clock::now() - started;
    if (took > std::chrono::milliseconds(250)) {  // a slow disk: Store answers late (persistence.md §10)
      spdlog::warn("store took {} ms", std::chrono::duration_cast<std::chrono::milliseconds>(took).count());
    }
    if (job.done) {
      boost::asio::post(io_,
                        [done = std::move(job.done), error = std::move(error)]() mutable { done(std::move(error)); });
    }
    {
      std::lock_guard lock(mutex_);
      busy_ = false;
    }
    idle_cv_.notify_all();
  }
}

}  // namespace mcemu::persistence
