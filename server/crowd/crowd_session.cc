#include "server/crowd/crowd_session.h"

#include <cmath>
#include <string>

#include <spdlog/spdlog.h>

#include "server/rpc/grpc_status.h"

namespace armature::server {
namespace {

std::string Named(uint32_t id) { return "character " + std::to_string(id) + ": "; }

Status CheckStart(const v1::CrowdStart& start, const Limits& limits) {
  const double fps = start.fps() == 0 ? 30 : start.fps();
  if (!std::isfinite(fps) || fps <= 0 || fps > limits.max_stream_fps)
    return Status::InvalidArgument("start.fps: " + std::to_string(fps) + " is not in (0, " +
                                   std::to_string(limits.max_stream_fps) + "]");
  if (!std::isfinite(start.budget_ms()) || start.budget_ms() < 0 || start.budget_ms() > limits.crowd_budget_ms)
    return Status::InvalidArgument("start.budget_ms: " + std::to_string(start.budget_ms()) + " is not in [0, " +
                                   std::to_string(limits.crowd_budget_ms) + "] (--crowd-budget-ms)");
  if (start.max_interval() > 255)
    return Status::InvalidArgument("start.max_interval: " + std::to_string(start.max_interval()) + " is over 255");
  if (!std::isfinite(start.share_quantum()) || start.share_quantum() > 1)
    return Status::InvalidArgument("start.share_quantum: must be finite and at most 1 second");
  if (!std::isfinite(start.duration()) || start.duration() < 0)
    return Status::InvalidArgument("start.duration: must be finite and >= 0");
  return Status::Ok();
}

}  // namespace

CrowdSession::~CrowdSession() {
  totals_->RemoveCharacters(static_cast<int64_t>(roots_.size()));
  spdlog::debug("crowd session done after {} ticks and {} commands, {} characters", frames_, commands_, roots_.size());
}

Status CrowdSession::Start(const CallStop& /*call*/, const Request& first) {
  if (!first.has_start()) return Status::InvalidArgument("start: required in the first message (fps, budget_ms)");
  const v1::CrowdStart& start = first.start();
  ARMATURE_RETURN_IF_ERROR(CheckStart(start, limits_));
  fps_ = start.fps() == 0 ? 30 : start.fps();
  budget_ms_ = start.budget_ms() == 0 ? limits_.crowd_budget_ms : start.budget_ms();
  duration_ = start.duration();
  CrowdTickOptions options;
  options.budget_us = budget_ms_ * 1000;
  options.max_interval = start.max_interval() == 0 ? 8 : start.max_interval();
  options.share_quantum = start.share_quantum() == 0 ? 1.0 / 120 : std::max(0.0, start.share_quantum());
  ticker_ = std::make_unique<CrowdTicker>(options);
  start_ = std::chrono::steady_clock::now();
  return Status::Ok();
}

Status CrowdSession::ApplyQueued() {
  if (queued_.empty()) return Status::Ok();
  const auto catalog = catalog_();
  for (auto& [number, command] : queued_) {
    Status st = Apply(*catalog, command);
    if (!st.ok()) {
      const uint32_t id = command.has_add()      ? command.add().id()
                          : command.has_update() ? command.update().id()
                                                 : command.remove();
      Refuse(number, id, st);
    }
  }
  queued_.clear();
  return Status::Ok();
}

Status CrowdSession::Apply(const Catalog& catalog, const Request& command) {
  switch (command.command_case()) {
    case Request::kAdd: return Add(catalog, command.add());
    case Request::kUpdate: return Update(catalog, command.update());
    case Request::kRemove: return Remove(command.remove());
    case Request::kStart: return Status::InvalidArgument("start: only the first message may start the session");
    default: return Status::InvalidArgument("command: none set (add, update or remove)");
  }
}

Status CrowdSession::Add(const Catalog& catalog, const v1::CrowdCharacter& message) {
  const uint32_t id = message.id();
  if (roots_.count(id)) return Status(StatusCode::kAlreadyExists, Named(id) + "the id is already in the crowd");
  if (roots_.size() >= static_cast<size_t>(limits_.max_crowd_characters))
    return Status::ResourceExhausted(Named(id) + "the session holds " + std::to_string(roots_.size()) +
                                     " characters, the limit --max-crowd-characters");
  ARMATURE_ASSIGN_OR_RETURN(ResolvedCharacter resolved, ResolveCharacter(catalog, message, motions_));
  ARMATURE_ASSIGN_OR_RETURN(resolved.numbers.clip, ClipIndexOf(resolved));
  if (!totals_->TryAddCharacter())
    return Status::ResourceExhausted(Named(id) + "the server's crowds hold " + std::to_string(totals_->characters()) +
                                     " characters, the limit --max-crowd-characters-total");
  if (Status st = ticker_->Add(resolved.numbers); !st.ok()) {
    totals_->RemoveCharacters(1);
    return st;
  }
  roots_.emplace(id, message.root());
  return Status::Ok();
}

Status CrowdSession::Update(const Catalog& catalog, const v1::CrowdCharacter& message) {
  auto held = roots_.find(message.id());
  if (held == roots_.end()) return Status::NotFound(Named(message.id()) + "no such id in the crowd");
  ARMATURE_ASSIGN_OR_RETURN(ResolvedCharacter resolved, ResolveCharacter(catalog, message, motions_));
  ARMATURE_ASSIGN_OR_RETURN(resolved.numbers.clip, ClipIndexOf(resolved));
  ARMATURE_RETURN_IF_ERROR(ticker_->Update(resolved.numbers));
  held->second = message.root();
  return Status::Ok();
}

Status CrowdSession::Remove(uint32_t id) {
  if (!roots_.erase(id)) return Status::NotFound(Named(id) + "no such id in the crowd");
  ARMATURE_RETURN_IF_ERROR(ticker_->Remove(id));
  totals_->RemoveCharacters(1);
  return Status::Ok();
}

StatusOr<uint32_t> CrowdSession::ClipIndexOf(const ResolvedCharacter& resolved) {
  ARMATURE_ASSIGN_OR_RETURN(uint32_t index,
                            resolved.motion ? ticker_->AddMotion(resolved.motion) : ticker_->AddClip(resolved.clip));
  if (index == clip_names_.size()) clip_names_.emplace_back(resolved.clip_name, resolved.skeleton_name);
  return index;
}

void CrowdSession::Refuse(uint64_t number, uint32_t id, const Status& status) {
  if (first_refusal_.ok()) first_refusal_ = status;
  if (errors_.size() >= kMaxErrors) {
    ++errors_dropped_;
    return;
  }
  v1::CrowdError& error = errors_.emplace_back();
  error.set_message(number);
  error.set_id(id);
  error.set_code(static_cast<int32_t>(ToGrpcStatus(status).error_code()));
  error.set_error(std::string(status.message()));
}

void CrowdSession::FillLayouts(Frame* frame) {
  for (; layouts_sent_ < clip_names_.size(); ++layouts_sent_) {
    const PoseLayout& layout = ticker_->layout(static_cast<uint32_t>(layouts_sent_));
    v1::CrowdLayout& out = *frame->add_new_layouts();
    out.set_layout(static_cast<uint32_t>(layouts_sent_));
    out.set_clip(clip_names_[layouts_sent_].first);
    out.set_skeleton(clip_names_[layouts_sent_].second);
    out.set_joints(layout.joints);
    for (uint16_t j : layout.translated) out.add_translated_joints(j);
    for (uint16_t j : layout.scaled) out.add_scaled_joints(j);
    for (const Trs& base : layout.base)
      for (int k = 0; k < 3; ++k) {
        out.add_base_translations(static_cast<float>(base.translation[k]));
        out.add_base_scales(static_cast<float>(base.scale[k]));
      }
    out.set_pose_bytes(static_cast<uint32_t>(layout.EncodedSize()));
    out.set_max_rotation_error(MaxEncodedRotationError());
  }
}

StatusOr<bool> CrowdSession::NextFrame(bool closed, Frame* frame) {
  const double time = static_cast<double>(frames_) / fps_;
  if (duration_ > 0 ? time >= duration_ - 1e-9 : closed) return false;
  // Over half a tick past its due time: late (the reactor writes frame k at start + k/fps at the earliest).
  const double due = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() - time;
  frame->Clear();
  if (Status st = ticker_->Tick(frames_, time, &tick_); !st.ok()) return Status(StatusCode::kInternal, st.message());
  frame->set_tick(frames_);
  frame->set_time(time);
  frame->mutable_ids()->Add(tick_.ids.begin(), tick_.ids.end());
  frame->mutable_layouts()->Add(tick_.clips.begin(), tick_.clips.end());
  frame->mutable_clip_times()->Add(tick_.clip_times.begin(), tick_.clip_times.end());
  frame->set_poses(tick_.poses.data(), tick_.poses.size());
  FillLayouts(frame);
  for (v1::CrowdError& error : errors_) *frame->add_errors() = std::move(error);
  if (errors_dropped_ > 0 && frame->errors_size() > 0)
    frame->mutable_errors(frame->errors_size() - 1)
        ->mutable_error()
        ->append(" (and " + std::to_string(errors_dropped_) + " more refusals not listed)");
  errors_.clear();
  errors_dropped_ = 0;
  v1::CrowdTickStats& stats = *frame->mutable_stats();
  stats.set_characters(static_cast<uint32_t>(ticker_->size()));
  stats.set_updated(static_cast<uint32_t>(tick_.ids.size()));
  stats.set_deferred(static_cast<uint32_t>(tick_.deferred));
  stats.set_reduced(static_cast<uint32_t>(tick_.reduced));
  stats.set_samples(static_cast<uint32_t>(tick_.samples));
  stats.set_budget_ms(budget_ms_);
  stats.set_work_ms(tick_.work_us / 1000);
  stats.set_late(due > 0.5 / fps_);
  totals_->CountTick(stats.late(), tick_.deferred, frame->ByteSizeLong());
  ++frames_;
  return true;
}

}  // namespace armature::server
