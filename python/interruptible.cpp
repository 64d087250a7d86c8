// glint — long work off the GIL, stopped by Ctrl-C (see interruptible.h).
#include "python/interruptible.h"

#include <chrono>
#include <exception>
#include <future>

namespace py = pybind11;

namespace glint::python {

std::optional<py::error_already_set> runInterruptibly(std::atomic<bool>& cancel,
                                                      const std::function<void()>& work) {
  std::optional<py::error_already_set> interrupt;
  std::future<void> done;
  {
    py::gil_scoped_release release;
    done = std::async(std::launch::async, work);
    while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      if (interrupt) continue;  // cancelled: waiting for the pass in flight to be dropped
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        interrupt.emplace();  // takes the raised exception, clearing it
        cancel.store(true);
      }
    }
  }
  if (interrupt) {
    try {
      done.get();
    } catch (const std::exception&) {  // the interrupt is the news
    }
    return interrupt;
  }
  done.get();  // rethrows what `work` threw
  return std::nullopt;
}

}  // namespace glint::python
