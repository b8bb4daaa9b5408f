// Errors that end a chapter program, each with its exit code (the table is in the book's
// maintainers page, book/docs/maintainers.md).
#pragma once
#include <stdexcept>
#include <string>

namespace course {

enum class ExitCode : int {
    Ok = 0,
    CheckFailed = 1,  // the program ran, but a result it verifies is wrong
    BadUsage = 2,     // command line: unknown option, missing value, absurd size
    BadInput = 3,     // an input file (OBJ, scene): the message names file:line
    GlProblem = 4,    // no context, GL too old, shader compile/link error (file:line)
};

// Thrown anywhere; caught once in course::run(), which prints the message and exits.
class Failure : public std::runtime_error {
public:
    Failure(ExitCode code, const std::string& message)
        : std::runtime_error(message), code_(code) {}
    ExitCode code() const { return code_; }

private:
    ExitCode code_;
};

[[noreturn]] inline void fail(ExitCode code, const std::string& message) {
    throw Failure(code, message);
}

}  // namespace course
