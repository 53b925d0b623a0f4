// retarget: a clip moved onto another skeleton, stored as a new asset; prints
// the new asset as `armature import` does, plus the joint pairs used and the
// joints left unmapped (--json: {"clip", "mapping", "unmapped"}).
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_context.h"

namespace armature::cli {
namespace {

v1::JointPair ParsePair(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size() || text.find('=', eq + 1) != std::string::npos)
    throw std::runtime_error("--map " + text + ": expected SOURCE=TARGET (a source joint, '=', a target joint)");
  v1::JointPair pair;
  pair.set_source(text.substr(0, eq));
  pair.set_target(text.substr(eq + 1));
  return pair;
}

void PrintText(const v1::RetargetClipResponse& r) {
  const v1::ClipInfo& c = r.clip();
  std::cout << "asset " << r.asset().name() << "\n  clip     " << c.name() << ": " << c.duration() << " s, "
            << c.frames() << " frames, skeleton " << c.skeleton() << "\n";
  std::cout << "mapping (" << r.mapping_size() << " pairs):\n";
  for (const auto& p : r.mapping()) std::cout << "  " << p.source() << " -> " << p.target() << "\n";
  auto list = [](const char* what, const auto& names) {
    std::cout << "unmapped " << what << " (" << names.size() << "):";
    for (const auto& n : names) std::cout << " " << n;
    std::cout << "\n";
  };
  list("source", r.unmapped().source());
  list("target", r.unmapped().target());
  for (const auto& w : r.warnings()) std::cerr << "warning: " << w << "\n";
}

}  // namespace

void AddRetargetCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("retarget",
                                 "Move a clip onto another skeleton (names mapped, rest poses "
                                 "compensated, root scaled) and store it as a new asset");
  auto clip = std::make_shared<std::string>();
  auto skeleton = std::make_shared<std::string>();
  auto pairs = std::make_shared<std::vector<std::string>>();
  auto name = std::make_shared<std::string>();
  auto feet = std::make_shared<bool>(false);
  auto replace = std::make_shared<bool>(false);
  cmd->add_option("CLIP", *clip, "The source clip")->required();
  cmd->add_option("--to", *skeleton, "The target skeleton")->required();
  cmd->add_option("--map", *pairs,
                  "SOURCE=TARGET: drive this target joint from this source joint (repeatable; "
                  "overrides the automatic map)");
  cmd->add_option("--name", *name,
                  "The new clip's name, a clip of the target skeleton (default <clip>_on_<skeleton>, dots as '_')");
  cmd->add_flag("--feet", *feet, "Keep the feet where the source plants them (two-bone IK per leg)");
  cmd->add_flag("--replace", *replace, "Replace an asset of the same name");
  cmd->callback([&ctx, clip, skeleton, pairs, name, feet, replace] {
    ctx.run = [&ctx, clip, skeleton, pairs, name, feet, replace] {
      v1::RetargetClipRequest request;
      request.set_clip(*clip);
      request.set_skeleton(*skeleton);
      request.set_name(*name);
      request.set_feet(*feet);
      request.set_replace(*replace);
      for (const std::string& p : *pairs) *request.add_map() = ParsePair(p);
      const v1::RetargetClipResponse r = ctx.MakeClient().RetargetClip(request);
      if (!ctx.json) {
        PrintText(r);
        return 0;
      }
      nlohmann::json j = {{"clip", ToJson(r.clip())},
                          {"mapping", nlohmann::json::array()},
                          {"unmapped", {{"source", nlohmann::json::array()}, {"target", nlohmann::json::array()}}}};
      for (const auto& p : r.mapping()) j["mapping"].push_back({{"source", p.source()}, {"target", p.target()}});
      for (const auto& n : r.unmapped().source()) j["unmapped"]["source"].push_back(n);
      for (const auto& n : r.unmapped().target()) j["unmapped"]["target"].push_back(n);
      if (r.warnings_size() > 0) j["warnings"] = std::vector<std::string>(r.warnings().begin(), r.warnings().end());
      PrintJson(j);
      return 0;
    };
  });
}

}  // namespace armature::cli
