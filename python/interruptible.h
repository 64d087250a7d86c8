// glint — long work from Python: off the GIL, stopped by Ctrl-C.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <functional>
#include <optional>

namespace glint::python {

// Runs `work` on a thread of its own with the GIL released, so other Python threads run
// meanwhile. The calling thread checks for signals every 50 ms (Python runs its handlers only
// in the main thread, between bytecodes; C++ rendering never reaches one): when a handler
// raises (Ctrl-C's KeyboardInterrupt), it sets `cancel` (which `work` watches), waits for it to
// return (a render drops the pass in flight) and returns that exception, to be raised once the
// caller has kept what was done. Without a signal it returns nullopt, or rethrows what `work`
// threw.
std::optional<pybind11::error_already_set> runInterruptibly(std::atomic<bool>& cancel,
                                                            const std::function<void()>& work);

}  // namespace glint::python
