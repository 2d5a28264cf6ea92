// Worker threads that cannot all be started (support/threads.h): the work is
// done by those that were, an exception on a thread reaches the caller, and
// the process is never ended by std::terminate.
#include <doctest/doctest.h>

#include <atomic>
#include <stdexcept>
#include <system_error>

#include "support/threads.h"

using namespace osplint;

namespace {

// Starts `allowed` threads, then fails as std::thread does without resources.
ThreadStarter failing_after(unsigned allowed, std::atomic<unsigned>& started) {
    return [allowed, &started](std::function<void()> f) {
        if (started.load() >= allowed)
            throw std::system_error(std::make_error_code(std::errc::resource_unavailable_try_again));
        ++started;
        return std::thread(std::move(f));
    };
}

}  // namespace

TEST_CASE("run_on_threads: every item is done by the threads that started") {
    for (unsigned allowed : {0u, 1u, 3u, 100u}) {
        std::atomic<unsigned> started{0};
        std::atomic<size_t> next{0}, done{0};
        auto work = [&] {
            for (size_t i; (i = next.fetch_add(1)) < 1000;) done.fetch_add(1);
        };
        const std::string error = run_on_threads(8, work, work, failing_after(allowed, started));
        CHECK(done.load() == 1000);
        CHECK(started.load() == std::min(allowed, 8u));
        if (allowed < 8) CHECK(error.find("could not start more than " + std::to_string(allowed) + " worker thread") == 0);
        else CHECK(error.empty());
    }
}

TEST_CASE("run_on_threads: an exception on a worker reaches the caller after the join") {
    std::atomic<int> runs{0};
    auto work = [&] {
        ++runs;
        throw std::runtime_error("worker failed");
    };
    CHECK_THROWS_WITH(run_on_threads(3, work, [] {}), "worker failed");
    CHECK(runs.load() == 3);
}
