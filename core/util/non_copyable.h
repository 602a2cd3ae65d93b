// The base of classes that own something a copy would release twice or share by mistake (a device, a file, a
// thread, a scope that restores state when it ends). Such a class declares its destructor, so it gets no implicit
// move either: it stays where it was made, as with deleted copy operations of its own.
#pragma once

namespace prism {

class NonCopyable {
public:
    NonCopyable(const NonCopyable&) = delete;
    NonCopyable& operator=(const NonCopyable&) = delete;

protected:
    NonCopyable() = default;
    ~NonCopyable() = default;
};

}  // namespace prism
