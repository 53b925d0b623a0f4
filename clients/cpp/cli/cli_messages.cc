#include "cli_messages.h"

#include <cstdlib>
#include <sstream>
#include <string_view>

#include "armature/base/closest_name.h"

namespace armature::cli {
namespace {

std::vector<const CLI::App*> Commands(const CLI::App& app) {
  return app.get_subcommands([](const CLI::App*) { return true; });
}

// A flag (--json) takes no value; any other option takes the next word unless written --name=value.
bool TakesNextWord(const CLI::Option& option, const std::string& word) {
  return option.get_type_size() != 0 && word.find('=') == std::string::npos;
}

// "--time", "--server", … : the long names `command` and the app both take.
std::vector<std::string> LongNames(const CLI::App& app, const CLI::App* command) {
  std::vector<std::string> names;
  for (const CLI::App* a : {command, &app}) {
    if (!a) continue;
    for (const CLI::Option* o : a->get_options())
      for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
  }
  return names;
}

std::string UnknownOption(const CLI::App& app, const CLI::App* command, const std::string& option) {
  const std::vector<std::string> names = LongNames(app, command);
  const std::vector<std::string_view> views(names.begin(), names.end());
  const std::string where = command ? command->get_name() + ": " : "";
  return where + "unknown option '" + option + "'" + DidYouMean(option, views);
}

std::string UnknownCommand(const CLI::App& app, const std::string& word) {
  std::vector<std::string_view> names;
  for (const CLI::App* c : Commands(app)) names.push_back(c->get_name());
  return "unknown command '" + word + "'" + DidYouMean(word, names) + " (commands: " + JoinNames(names) + ")";
}

bool IsConnectionFailure(const std::string& message) {
  return message.find("connect") != std::string::npos || message.find("DNS resolution") != std::string::npos;
}

// CLI11's numeric validators print their bounds with std::to_string: 300 digits for DBL_MAX.
CLI::Validator NumberAbove(double bound, bool inclusive, const std::string& words) {
  return CLI::Validator(
      [bound, inclusive, words](std::string& input) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(input.c_str(), &end);
        if (end == input.c_str() || *end != '\0') return "must be a number, got '" + input + "'";
        return (inclusive ? v >= bound : v > bound) ? "" : "must be " + words + ", got " + input;
      },
      inclusive ? "NUMBER >= 0" : "NUMBER > 0");
}

}  // namespace

std::string UnknownWordMessage(const CLI::App& app, const std::vector<std::string>& args) {
  const CLI::App* command = nullptr;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& word = args[i];
    if (word == "--") break;
    if (word.rfind("-", 0) == 0) {
      const std::string name = word.substr(0, word.find('='));
      const CLI::Option* option = command ? command->get_option_no_throw(name) : nullptr;
      if (!option) option = app.get_option_no_throw(name);
      if (!option && word.rfind("--", 0) == 0) return UnknownOption(app, command, name);
      if (option && TakesNextWord(*option, word)) ++i;
      continue;
    }
    if (command) continue;  // a positional argument of the command
    for (const CLI::App* c : Commands(app))
      if (c->check_name(word)) command = c;
    if (!command) return UnknownCommand(app, word);
  }
  return "";
}

std::string CallErrorMessage(const client::ClientError& error, const std::string& target, const CLI::App* command) {
  std::string message = std::string(client::StatusCodeName(error.code())) + ": " + error.what();
  if (error.code() == grpc::StatusCode::UNAVAILABLE && IsConnectionFailure(error.what())) {
    return "no armature-server answers at " + target + " (" + message +
           ").\nStart one in the repository with `make run` (or build/bin/armature-server), or name another with "
           "--server HOST:PORT or ARMATURE_SERVER.";
  }
  if (error.code() == grpc::StatusCode::ALREADY_EXISTS && command && command->get_option_no_throw("--replace")) {
    // The server names the API's field; on the command line it is a flag.
    const std::string field_hint = " (set replace to overwrite it)";
    if (const size_t at = message.find(field_hint); at != std::string::npos) message.erase(at, field_hint.size());
    message += " (add --replace to overwrite it)";
  }
  return message;
}

CLI::Validator PositiveNumber() { return NumberAbove(0, false, "greater than 0"); }
CLI::Validator NonNegativeNumber() { return NumberAbove(0, true, "0 or more"); }

CLI::Validator OneOf(const std::vector<std::string>& names) { return CLI::IsMember(names, CLI::ignore_case); }

}  // namespace armature::cli
