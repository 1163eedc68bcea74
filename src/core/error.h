// The project's one error type. Every failure a user can meet surfaces as
// cm::Error with a sentence that names what failed (file, node, stage).
#pragma once
#include <stdexcept>
#include <string>

namespace cm {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// Raised when the user cancels (Ctrl-C) or an interrupter asks to stop.
class Cancelled : public Error {
public:
    Cancelled() : Error("cancelled by the user") {}
};

} // namespace cm
