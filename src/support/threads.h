// Worker threads that may not all start: under a memory or process limit a
// thread can fail to start (std::system_error), and the work then runs on
// those that did, never std::terminate.
#pragma once

#include <functional>
#include <string>
#include <thread>

namespace osplint {

// Starts one thread running its argument (tests replace it with one that fails).
using ThreadStarter = std::function<std::thread(std::function<void()>)>;

// Starts up to `threads` threads running `work`, runs `here` on this thread
// and joins them all. When no thread could be started, `work` runs on this
// thread before `here`. `work` must share its items between the threads that
// run it (an atomic counter), whatever their number. Returns "" when every
// thread started, else why fewer did.
std::string run_on_threads(unsigned threads, const std::function<void()>& work, const std::function<void()>& here,
                           const ThreadStarter& start = {});

}  // namespace osplint
