// A value shared between copies until one of them changes it (copy on
// write): for the parts of a state that is copied at every block while they
// rarely change. Two are equal when they share the value or hold equal ones.
#pragma once

#include <memory>

namespace osplint {

template <class T>
class SharedValue {
public:
    const T& get() const {
        static const T none{};
        return p_ ? *p_ : none;
    }
    // The value to change: copied first when another copy shares it.
    T& edit() {
        if (!p_ || p_.use_count() > 1) p_ = std::make_shared<T>(get());
        return *p_;
    }
    // The value as shared (nullptr: none set): keeping it keeps the value
    // alive and unchanged, so that the same pointer later is the same value.
    std::shared_ptr<const T> shared() const { return p_; }
    // Whether the two hold the same value, not only equal ones.
    bool shares(const SharedValue& o) const { return p_ == o.p_; }
    friend bool operator==(const SharedValue& a, const SharedValue& b) { return a.shares(b) || a.get() == b.get(); }

private:
    std::shared_ptr<T> p_;
};

}  // namespace osplint
