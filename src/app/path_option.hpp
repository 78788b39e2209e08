#pragma once
// The check shared by the commands' file options (-o, --lammps-data): a path names a file.
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

}  // namespace jamsim::app
