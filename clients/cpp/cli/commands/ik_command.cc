// ik: one inverse kinematics solve, printed like `armature pose`.
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>

#include "cli_context.h"
#include "cli_messages.h"
#include "files/pose_output.h"

namespace armature::cli {
namespace {

const std::map<std::string, v1::IkSolver> kSolvers = {
    {"dls", v1::DLS}, {"ccd", v1::CCD}, {"fabrik", v1::FABRIK}, {"two-bone", v1::TWO_BONE}, {"aim", v1::AIM}};

// --free-root (both) or --free-root=rotation|translation|both.
const std::map<std::string, v1::FreeRoot> kFreeRoots = {{"", v1::ROOT_FIXED},
                                                        {"rotation", v1::ROOT_ROTATION},
                                                        {"translation", v1::ROOT_TRANSLATION},
                                                        {"both", v1::ROOT_ROTATION_AND_TRANSLATION}};

// "stalled" from STOP_STALLED.
std::string StopName(v1::IkStop stop) {
  std::string name = v1::IkStop_Name(stop);
  if (name.rfind("STOP_", 0) == 0) name.erase(0, 5);
  for (char& c : name) c = c == '_' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

// "LeftWrist=10,95.5,-3" → an effector with a target position.
v1::IkEffector ParseEffector(const std::string& text) {
  const auto bad = [&] {
    return std::runtime_error("--effector '" + text + "': expected JOINT=x,y,z (a world position)");
  };
  const size_t eq = text.rfind('=');
  if (eq == std::string::npos || eq == 0) throw bad();
  v1::IkEffector e;
  e.set_joint(text.substr(0, eq));
  const char* p = text.c_str() + eq + 1;
  for (int k = 0; k < 3; ++k) {
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p || *end != (k < 2 ? ',' : '\0')) throw bad();
    e.add_target_position(v);
    p = end + (k < 2 ? 1 : 0);
  }
  return e;
}

struct IkFlags {
  std::string skeleton;
  std::vector<std::string> effectors;
  std::string solver = "dls";
  std::string from_clip;
  double time = 0;
  int max_iterations = 0;
  double tolerance = 0;
  std::string root;
  std::string free_root;
  std::string space = "world";
};

}  // namespace

void AddIkCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("ik", "Solve inverse kinematics: a pose putting joints at target positions");
  auto f = std::make_shared<IkFlags>();
  cmd->add_option("SKELETON", f->skeleton, "Skeleton name")->required();
  cmd->add_option("--effector,-e", f->effectors, "JOINT=x,y,z: a world target for a joint (repeatable)")
      ->required()
      ->allow_extra_args(false);
  cmd->add_option("--solver", f->solver, "dls, ccd, fabrik, two-bone or aim")
      ->capture_default_str()
      ->transform(OneOf({"dls", "ccd", "fabrik", "two-bone", "aim"}));
  auto* clip = cmd->add_option("--from-clip", f->from_clip, "Start from this clip's pose (default: the rest pose)");
  cmd->add_option("--time,-t", f->time, "Clip time of the start pose, in seconds")->needs(clip);
  cmd->add_option("--max-iterations", f->max_iterations, "Solver iterations (default: the server's, 200)")
      ->check(PositiveNumber());
  cmd->add_option("--tolerance", f->tolerance, "Position tolerance, world units (default: 1e-4 x chain length)")
      ->check(PositiveNumber());
  cmd->add_option("--root", f->root,
                  "Only joints below this one move (default: those above the effectors but the skeleton root)");
  cmd->add_flag("--free-root{both}", f->free_root,
                "Let the skeleton root (the hips) turn and move too; --free-root=rotation or =translation for one");
  cmd->add_option("--space", f->space, "Print the pose in local or world space")
      ->capture_default_str()
      ->transform(OneOf({"local", "world"}));
  cmd->callback([&ctx, f] {
    ctx.run = [&ctx, f] {
      v1::SolveIkRequest request;
      request.set_skeleton(f->skeleton);
      for (const std::string& e : f->effectors) *request.add_effectors() = ParseEffector(e);
      request.set_solver(kSolvers.at(f->solver));
      if (!f->from_clip.empty()) {
        request.mutable_from_clip()->set_clip(f->from_clip);
        request.mutable_from_clip()->set_time(f->time);
      }
      request.mutable_options()->set_max_iterations(f->max_iterations);
      request.mutable_options()->set_position_tolerance(f->tolerance);
      request.set_root(f->root);
      const auto free_root = kFreeRoots.find(f->free_root);
      if (free_root == kFreeRoots.end())
        throw std::runtime_error("--free-root='" + f->free_root + "': expected rotation, translation or both");
      request.set_free_root(free_root->second);
      client::Client client = ctx.MakeClient();
      const v1::SolveIkResponse response = client.SolveIk(request);
      const v1::Skeleton skeleton = client.GetSkeleton(response.skeleton());
      const v1::Pose& pose = f->space == "world" ? response.world() : response.local();
      // An unreachable target is an answer, not an error: exit 0 with converged false.
      if (ctx.json) {
        nlohmann::json residuals = nlohmann::json::array();
        for (const v1::IkResidual& r : response.residuals())
          residuals.push_back({{"joint", r.joint()},
                               {"positionError", r.position_error()},
                               {"rotationError", r.rotation_error()},
                               {"reached", r.reached()}});
        PrintJson({{"skeleton", response.skeleton()},
                   {"space", f->space},
                   {"joints", PoseJointsJson(skeleton, response.joints(), pose)},
                   {"residuals", residuals},
                   {"converged", response.converged()},
                   {"stop", StopName(response.stop())},
                   {"iterations", response.iterations()}});
      } else {
        std::printf("skeleton %s: %s after %d iterations (%s; %s space)\n", response.skeleton().c_str(),
                    response.converged() ? "converged" : "NOT converged", response.iterations(),
                    StopName(response.stop()).c_str(), f->space.c_str());
        PrintPoseTable(skeleton, response.joints(), pose);
        for (const v1::IkResidual& r : response.residuals())
          std::printf("residual %-24s position %.6g rotation %.6g rad %s\n", r.joint().c_str(), r.position_error(),
                      r.rotation_error(), r.reached() ? "reached" : "NOT reached");
      }
      return 0;
    };
  });
}

}  // namespace armature::cli
