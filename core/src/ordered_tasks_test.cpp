// OrderedTasks: every task runs once, on the threads asked for, results are
// consumed in order, and a failed task's exception reaches the caller.
#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <set>
#include <stdexcept>

#include "ordered_tasks.h"

using gw::OrderedTasks;

TEST_CASE("each task runs once and wait(k) sees its result, for one thread and several") {
    for (int threads : {1, 2, 5}) {
        const size_t n = 200;
        std::vector<std::atomic<int>> runs(n);
        std::vector<size_t> result(n, 0);
        std::mutex mu;
        std::set<std::thread::id> ran_on;
        {
            OrderedTasks tasks(n, threads, [&](size_t k) {
                ++runs[k];
                result[k] = k * k;
                std::this_thread::sleep_for(std::chrono::microseconds(200));
                std::lock_guard<std::mutex> lock(mu);
                ran_on.insert(std::this_thread::get_id());
            }, "gw-test");
            CHECK(tasks.threads() == threads);
            for (size_t k = 0; k < n; ++k) {
                tasks.wait(k);
                CHECK(result[k] == k * k);   // written by whichever thread ran it, visible here
            }
        }
        for (size_t k = 0; k < n; ++k) CHECK(runs[k].load() == 1);
        if (threads == 1) {
            CHECK(ran_on.size() == 1);
            const bool on_caller = *ran_on.begin() == std::this_thread::get_id();
            CHECK(on_caller);   // no worker: the caller ran them all
        } else {
            CHECK(ran_on.size() >= 2);
        }
    }
}

TEST_CASE("a task's exception reaches the caller and later tasks are not all run") {
    const size_t n = 1000;
    std::atomic<size_t> ran{0};
    OrderedTasks tasks(n, 3, [&](size_t k) {
        ++ran;
        if (k == 10) throw std::runtime_error("task 10 failed");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));   // (1000 of them: a second of work to stop early)
    }, "gw-test");
    for (size_t k = 0; k < 10; ++k) tasks.wait(k);
    CHECK_THROWS_WITH(tasks.wait(10), "task 10 failed");
    CHECK_THROWS_WITH(tasks.wait(500), "task 10 failed");   // a later one: the first failure
    CHECK(ran.load() < n);
}

TEST_CASE("no tasks, and fewer tasks than threads") {
    { OrderedTasks none(0, 4, [](size_t) { FAIL("no task to run"); }, "gw-test"); }
    int sum = 0;
    OrderedTasks two(2, 8, [&](size_t k) { if (k == 1) sum += 1; }, "gw-test");
    CHECK(two.threads() == 2);   // no worker without a task to take
    two.wait(0);
    two.wait(1);
    CHECK(sum == 1);
}

TEST_CASE("for_each_range covers every item once, in ranges of at least `least`, and rethrows") {
    for (int threads : {1, 2, 3, 8})
        for (size_t n : {size_t(0), size_t(1), size_t(99), size_t(100), size_t(1000), size_t(4097)}) {
            const size_t least = 50;
            std::vector<std::atomic<int>> seen(n);
            std::mutex mu;
            std::vector<std::pair<size_t, size_t>> ranges;
            gw::for_each_range(n, threads, least, [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) ++seen[i];
                std::lock_guard<std::mutex> lock(mu);
                ranges.emplace_back(b, e);
            }, "gw-test");
            for (size_t i = 0; i < n; ++i) CHECK(seen[i].load() == 1);
            if (threads == 1 || n < 2 * least) {
                CHECK(ranges.size() == (n ? 1u : 0u));   // one call on the caller's thread (none for no items)
            } else {
                CHECK(ranges.size() >= 2);
                CHECK(ranges.size() <= size_t(4 * threads));
                for (const auto& r : ranges) CHECK(r.second - r.first >= least);
            }
        }
    CHECK_THROWS_WITH(gw::for_each_range(10000, 4, 10, [](size_t b, size_t) {
        if (b > 0) throw std::runtime_error("a range failed");
    }, "gw-test"), "a range failed");
}
