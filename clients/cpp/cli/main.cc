// `armature`: the command-line client. Every error exits non-zero with the
// server's message.
#include <iostream>
#include <string>
#include <vector>

#include "armature/build_info.h"
#include "cli_context.h"
#include "cli_messages.h"

int main(int argc, char** argv) {
  using namespace armature::cli;
  CLI::App app{"armature: command-line client of armature-server"};
  CliContext ctx;
  // Global options may come before or after the subcommand: a subcommand hands
  // options it does not know to the app (fallthrough, inherited by every
  // subcommand added below), so `armature list --server h:1` works like
  // `armature --server h:1 list`.
  app.fallthrough();
  app.footer("Global options (--server, --token, --ca-file, --timeout, --json) go before or after the subcommand.\n");
  app.set_version_flag("--version", armature::build_info::VersionLine("armature"),
                       "Print the version and git commit, then exit");
  app.add_option("--server", ctx.server, "Server address HOST:PORT (default $ARMATURE_SERVER, else localhost:50051)");
  app.add_option("--token", ctx.token, "Bearer token (default $ARMATURE_TOKEN)");
  app.add_option("--ca-file", ctx.ca_file, "Use TLS, trusting this CA certificate (default $ARMATURE_CA_FILE)");
  app.add_option("--timeout", ctx.timeout_seconds, "Deadline of each call, in seconds")
      ->capture_default_str()
      ->check(PositiveNumber());
  app.add_flag("--json", ctx.json, "Print JSON instead of text (import and info always print JSON)");
  app.require_subcommand(1);

  AddImportCommand(app, ctx);
  AddListCommand(app, ctx);
  AddInfoCommand(app, ctx);
  AddPoseCommand(app, ctx);
  AddStreamCommand(app, ctx);
  AddPlayCommand(app, ctx);
  AddCrowdCommand(app, ctx);
  AddIkCommand(app, ctx);
  AddExportCommand(app, ctx);
  AddCreateClipCommand(app, ctx);
  AddDeleteCommand(app, ctx);
  AddHealthCommand(app, ctx);
  AddDeformCommand(app, ctx);
  AddSkinCommand(app, ctx);
  AddRetargetCommand(app, ctx);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // A mistyped command or option: name it and the closest one, rather than what CLI11 checked first.
    const std::vector<std::string> args(argv + 1, argv + argc);
    const std::string unknown = e.get_exit_code() == 0 ? "" : UnknownWordMessage(app, args);
    if (unknown.empty()) return app.exit(e);
    std::cerr << "error: " << unknown << "\nRun with --help for more information.\n";
    return e.get_exit_code();
  }
  try {
    return ctx.run ? ctx.run() : 0;
  } catch (const armature::client::ClientError& e) {
    const auto parsed = app.get_subcommands();
    std::cerr << "error: " << CallErrorMessage(e, ctx.Target(), parsed.empty() ? nullptr : parsed[0]) << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
