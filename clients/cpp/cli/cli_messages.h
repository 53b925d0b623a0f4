// Messages a user can act on: what the CLI prints instead of CLI11's or
// gRPC's own words when a command, an option or the server is not there.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "armature/client.h"

namespace armature::cli {

// For a failed parse: "unknown command 'psoe'; did you mean 'pose'?" or
// "pose: unknown option '--tme'; did you mean '--time'?" when `args` (argv
// without the program) holds a command or a long option `app` does not know;
// "" when it holds none (CLI11's message then says what is wrong).
std::string UnknownWordMessage(const CLI::App& app, const std::vector<std::string>& args);

// What a failed call prints after "error: ": the code and the server's
// message, and for an unreachable server its address and how to start one;
// an existing asset names `--replace` when `command` has it.
std::string CallErrorMessage(const client::ClientError& error, const std::string& target, const CLI::App* command);

// Validators with short messages (CLI11's PositiveNumber prints its range as
// 300-digit numbers): "must be greater than 0, got 0".
CLI::Validator PositiveNumber();
CLI::Validator NonNegativeNumber();
// One of `names`, in any case (as the REST gateway takes enums), stored as
// written in `names`: use with ->transform.
CLI::Validator OneOf(const std::vector<std::string>& names);

}  // namespace armature::cli
