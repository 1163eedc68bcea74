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

/// A mistake on the command line (an unknown --set node or parameter, a value that does
/// not parse): the command exits with status 2, as for an unknown option.
class UsageError : public Error {
public:
    explicit UsageError(const std::string& what) : Error(what) {}
};

/// Raised when the user cancels (Ctrl-C) or an interrupter asks to stop.
class Cancelled : public Error {
public:
    Cancelled() : Error("cancelled by the user") {}
    /// `where` says where the stop took effect ("node \"write\" (mesh.write): stopped at 4%").
    explicit Cancelled(const std::string& where) : Error(where) {}
};

} // namespace cm
