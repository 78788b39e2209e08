#pragma once
// Checks shared by the commands' options: a file path that names a file, a count >= 1.
#include <cerrno>
#include <cstdlib>
#include <string>

#include <CLI/CLI.hpp>

namespace jamsim::app {

/// Refuses an empty path (`-o ""`, an unset shell variable) before any work: a replica would
/// otherwise run to the end and fail at its write, and `merge -o ""` take its first input as
/// the output. CLI11 puts the option's name before the message ("--output: value '' ...").
inline CLI::Validator nonempty_path() {
    return CLI::Validator(
        [](std::string& v) -> std::string {
            return v.empty() ? "value '' is not allowed: the path of a file (an empty path names none)" : "";
        },
        "FILE");
}

/// A whole number >= 1 of `what` ("replicas", "ranks"); CLI11's own PositiveNumber printed
/// "Value 0 not in range 0.000000 to 1.79769e+308" (300 digits of it).
inline CLI::Validator count_at_least_one(const std::string& what) {
    return CLI::Validator(
        [what](std::string& v) -> std::string {
            char* end = nullptr;
            const long long n = std::strtoll(v.c_str(), &end, 10);
            return end != v.c_str() && *end == '\0' && n >= 1
                       ? ""
                       : "value " + v + " is not allowed: a whole number of " + what + " >= 1";
        },
        "COUNT >= 1");
}

/// A whole number in decimal digits that fits 64 bits: no sign (CLI11 read "-1" into an
/// unsigned option as 2^64 - 1), no hexadecimal, no exponent.
inline CLI::Validator whole_number() {
    return CLI::Validator(
        [](std::string& v) -> std::string {
            const bool digits = !v.empty() && v.find_first_not_of("0123456789") == std::string::npos;
            errno = 0;
            if (digits) (void)std::strtoull(v.c_str(), nullptr, 10);
            return digits && errno != ERANGE
                       ? ""
                       : "value " + v + " is not allowed: a whole number from 0 to 18446744073709551615 in decimal";
        },
        "INTEGER >= 0");
}

}  // namespace jamsim::app
