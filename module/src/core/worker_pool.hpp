// Internal: the threads that core work is split over (batch shading, the reference's tables).
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace aerial::detail {

/// Threads that outlive the calls: a batch split over threads pays for no thread creation. One
/// batch at a time uses them; a call that finds them busy (another thread of the application is
/// in shade_into) works alone. Workers are created on first need, up to the largest number of
/// threads asked for, and joined at exit. A task that itself asks for the pool (the reference
/// model shaded in a batch, which builds its tables on first use) finds it busy and works alone.
class WorkerPool {
  public:
    static WorkerPool& instance() {
        static WorkerPool pool;
        return pool;
    }

    /// Runs task(first, last) over the items [0, items) in contiguous pieces, on the calling
    /// thread and up to min(threads, items) - 1 workers; returns the number of threads the work
    /// was offered to. Pieces are guided: each is the items left over twice the threads (at
    /// least min_piece), so the first pieces are large and the last ones small, and the threads
    /// finish together whenever one of them started late or was slowed down. A worker that has
    /// not woken up by the time every piece is taken is not waited for: on a machine whose other
    /// cores are busy the caller does the work alone instead of waiting for a time slice.
    unsigned run(unsigned threads, std::size_t items, std::size_t min_piece,
                 const std::function<void(std::size_t, std::size_t)>& task) {
        std::unique_lock<std::mutex> batch(batch_mutex_, std::try_to_lock);
        // In a child of fork() the workers are gone: it works alone.
        const bool usable = batch.owns_lock() && items > 1 && same_process();
        unsigned helpers = usable ? grow(std::min(threads - 1, kMaxWorkers)) : 0u;
        helpers = static_cast<unsigned>(std::min<std::size_t>(helpers, items - 1));
        if (helpers == 0) {
            if (items > 0) task(0, items);
            return 1;
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            task_ = &task;
            items_ = items;
            min_piece_ = std::max<std::size_t>(min_piece, 1);
            parts_ = 2 * (std::size_t(helpers) + 1);
            next_.store(0, std::memory_order_relaxed);
            seats_ = helpers;
            running_ = helpers;
            ++generation_;
        }
        wake_.notify_all();
        work();
        std::unique_lock<std::mutex> lock(mutex_);
        // Every piece is taken: seats not yet taken are withdrawn, only workers at work are
        // waited for.
        running_ -= seats_;
        seats_ = 0;
        done_.wait(lock, [this] { return running_ == 0; });
        task_ = nullptr;
        return helpers + 1;
    }

    ~WorkerPool() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (auto& w : workers_) w.join();
    }

  private:
    /// Workers at most, whatever BatchSettings::threads asks for.
    static constexpr unsigned kMaxWorkers = 255;

    WorkerPool() = default;

    bool same_process() const {
#if defined(__unix__) || defined(__APPLE__)
        return getpid() == pid_;
#else
        return true;
#endif
    }

    /// At least `helpers` workers if threads can be had; returns how many there are.
    unsigned grow(unsigned helpers) {
        while (workers_.size() < helpers) {
            try {
                workers_.emplace_back([this] { loop(); });
            } catch (const std::system_error&) {
                break;  // no more threads to be had: work with those there are
            }
        }
        return static_cast<unsigned>(std::min<std::size_t>(workers_.size(), helpers));
    }

    void work() {
        std::size_t first = next_.load(std::memory_order_relaxed);
        for (;;) {
            std::size_t last;
            do {
                if (first >= items_) return;
                const std::size_t left = items_ - first;
                last = first + std::min(left, std::max(min_piece_, left / parts_));
            } while (!next_.compare_exchange_weak(first, last, std::memory_order_relaxed));
            (*task_)(first, last);
            first = next_.load(std::memory_order_relaxed);
        }
    }

    void loop() {
        std::uint64_t seen = 0;
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            wake_.wait(lock, [&] { return stop_ || (generation_ != seen && seats_ > 0); });
            if (stop_) return;
            seen = generation_;
            --seats_;
            lock.unlock();
            work();
            lock.lock();
            if (--running_ == 0) done_.notify_one();
        }
    }

    std::mutex batch_mutex_;  // one batch at a time
    std::mutex mutex_;        // guards everything below
    std::condition_variable wake_, done_;
    std::vector<std::thread> workers_;
    const std::function<void(std::size_t, std::size_t)>* task_ = nullptr;
    std::size_t items_ = 0;
    std::size_t min_piece_ = 1;
    std::size_t parts_ = 2;
    std::atomic<std::size_t> next_{0};
    unsigned seats_ = 0;    // workers still to join the current batch
    unsigned running_ = 0;  // workers of the current batch not yet done
    std::uint64_t generation_ = 0;
    bool stop_ = false;
#if defined(__unix__) || defined(__APPLE__)
    const pid_t pid_ = getpid();  // the process the workers were started in
#endif
};

}  // namespace aerial::detail
