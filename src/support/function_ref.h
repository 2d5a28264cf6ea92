// A reference to a callable, for the callbacks of hot paths: calling it is an
// indirect call, and making it never allocates (a std::function holding a
// lambda that captures more than two pointers does, at every call of the
// function it is passed to). It does not own the callable: it must outlive
// the reference, as a lambda passed as an argument does.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>

namespace osplint {

template <class Signature>
class FunctionRef;

template <class R, class... Args>
class FunctionRef<R(Args...)> {
public:
    template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, FunctionRef> &&
                                                std::is_invocable_r_v<R, F&, Args...>>>
    FunctionRef(F&& f) noexcept  // NOLINT(google-explicit-constructor): takes lambdas as they are passed
        : object_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
          call_([](void* o, Args... args) -> R {
              return (*static_cast<std::add_pointer_t<std::remove_reference_t<F>>>(o))(std::forward<Args>(args)...);
          }) {}

    R operator()(Args... args) const { return call_(object_, std::forward<Args>(args)...); }

private:
    void* object_;
    R (*call_)(void*, Args...);
};

}  // namespace osplint
