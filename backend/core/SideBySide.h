#pragma once

#include <exception>
#include <future>
#include <optional>
#include <type_traits>
#include <utility>

namespace ambler {

// `first()` on the calling thread and `second()` on a thread of its own, at
// once. Returns both results; when both throw, `first`'s error is the one
// raised, as when they run one after the other.
template <class First, class Second>
auto sideBySide(First&& first, Second&& second) {
  using A = std::invoke_result_t<First&>;
  using B = std::invoke_result_t<Second&>;
  auto later = std::async(std::launch::async, std::forward<Second>(second));
  std::exception_ptr error;
  std::optional<A> a;
  try {
    a.emplace(first());
  } catch (...) {
    error = std::current_exception();
  }
  later.wait();
  if (error) std::rethrow_exception(error);
  B b = later.get();
  return std::pair<A, B>(std::move(*a), std::move(b));
}

}  // namespace ambler
