#include "support/threads.h"

#include <exception>
#include <mutex>
#include <vector>

namespace osplint {

std::string run_on_threads(unsigned threads, const std::function<void()>& work, const std::function<void()>& here,
                           const ThreadStarter& start) {
    // An exception thrown by `work` on a thread is handed to this one, after
    // the join: a thread never ends the process, nor does a thread left joinable.
    std::mutex mu;
    std::exception_ptr failure;
    auto guarded = [&] {
        try {
            work();
        } catch (...) {
            std::lock_guard<std::mutex> lock(mu);
            if (!failure) failure = std::current_exception();
        }
    };
    const bool any = threads > 0;
    std::vector<std::thread> pool;
    std::string error;
    try {
        pool.reserve(threads);
    } catch (const std::exception& e) {
        error = std::string("could not start the worker threads (") + e.what() + ")";
        threads = 0;
    }
    for (unsigned k = 0; k < threads; ++k) {
        try {
            pool.push_back(start ? start(guarded) : std::thread(guarded));
        } catch (const std::exception& e) {
            error = "could not start more than " + std::to_string(k) + " worker thread" + (k == 1 ? "" : "s") +
                    " (" + e.what() + ")";
            break;
        }
    }
    try {
        if (pool.empty() && any) work();
        if (here) here();
    } catch (...) {
        std::lock_guard<std::mutex> lock(mu);
        if (!failure) failure = std::current_exception();
    }
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    return error;
}

}  // namespace osplint
