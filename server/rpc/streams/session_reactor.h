// One bidirectional session (IK, deformation, playback, …) run for its
// logic: the one place that admits it, reads, answers or paces its frames,
// writes, and ends it (the call's deadline and cancellation given to the
// logic as a CallStop, errors mapped once through grpc_status.h). The logic
// knows nothing of gRPC. Every `Session` has
//   using Request;
//   static constexpr SessionKind kKind;   // its place in SessionAdmission
//   static constexpr const char* kName;   // "IkSession": logs, exceptions
// and is one of two shapes:
// - answering (IK, deformation): `using Response;`
//     Status Start(const CallStop& call, const Request& first, Response* response);
//     Status Answer(const Request& next, Response* response);
//   Reads, answers and writes go strictly in turn (one operation in
//   flight), so answers keep the order of the messages.
// - paced (playback): `using Frame;` (with a wall_time the reactor sets)
//     Status Start(const CallStop& call, const Request& first);
//     double fps() const;  uint64_t frames() const;
//     void Queue(Request command);  size_t queued() const;
//     Status ApplyQueued();
//     StatusOr<bool> NextFrame(bool closed, Frame* frame);  // false: over
//   Reads (commands) and paced writes run side by side: frame k is due at
//   start + k/fps (the FrameScheduler paces it, as PacedStreamReactor does
//   for streams) and is filled when frame k−1's write is done, applying the
//   commands read until then. At kMaxQueued (64, or the session's own) waiting commands reading pauses
//   until the next frame takes them (no unbounded memory). A session with a
//   write_timeout_seconds() > 0 is cancelled when a write stays blocked that long.
// Callbacks run under one lock; the logic is freed, and the session's
// place given back, before the client hears the session is over.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <utility>

#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include "armature/base/status.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/call_stop.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/streams/frame_scheduler.h"
#include "server/rpc/streams/session_admission.h"
#include "server/rpc/streams/stream_admission.h"
#include "server/rpc/work/elastic_thread_pool.h"

namespace armature::server {

template <class Session>
concept PacedSession = requires {
  typename Session::Frame;
};

// What a session writes: its answers, or its paced frames.
template <class Session>
struct SessionOutput {
  using type = typename Session::Response;
};
template <PacedSession Session>
struct SessionOutput<Session> {
  using type = typename Session::Frame;
};

// Where a session's work runs beside gRPC's callback threads.
struct SessionRunners {
  ElasticThreadPool* start_pool = nullptr;  // runs Start when set (a setup that may take seconds)
  FrameScheduler* scheduler = nullptr;      // paces the frames; required by paced sessions
};

// A paced session's queue bound: its own kMaxQueued when it has one (a crowd
// adds thousands of characters at once), else 64.
template <class Session>
constexpr size_t MaxQueuedOf() {
  if constexpr (requires { Session::kMaxQueued; })
    return Session::kMaxQueued;
  else
    return 64;
}

// How long a paced session's write may stay blocked (a client that stops
// reading) before the call is cancelled: the session's
// write_timeout_seconds() (a server option), else 0 (never).
template <class Session>
double WriteTimeoutOf(const Session& session) {
  if constexpr (requires { session.write_timeout_seconds(); })
    return session.write_timeout_seconds();
  else
    return 0;
}

template <class Session>
class SessionReactor final
    : public grpc::ServerBidiReactor<typename Session::Request, typename SessionOutput<Session>::type> {
  static constexpr bool kPaced = PacedSession<Session>;
  using Output = typename SessionOutput<Session>::type;

 public:
  static constexpr size_t kMaxQueued = MaxQueuedOf<Session>();  // commands waiting for a paced session's next frame

  // When `sessions` refuses the client a place, the call ends at once with
  // its RESOURCE_EXHAUSTED.
  SessionReactor(grpc::CallbackServerContext* context, SessionAdmission& sessions, StreamAdmission::Ticket stream,
                 std::unique_ptr<Session> session, SessionRunners runners = {})
      : context_(context),
        stream_(std::move(stream)),
        runners_(runners),
        session_(std::move(session)),
        write_timeout_(WriteTimeoutOf(*session_)) {
    std::lock_guard lock(mu_);
    auto ticket = sessions.Admit(*context, Session::kKind);
    if (!ticket.ok()) {
      End(ToGrpcStatus(ticket.status()));
      return;
    }
    ticket_ = std::move(*ticket);
    call_ = CallStopOf(*context);
    ReadNext();
  }

  void OnReadDone(bool ok) override {
    Guard([&] { ReadDone(ok); });
  }
  void OnWriteDone(bool ok) override {
    Guard([&] { WriteDone(ok); });
  }
  // A paced session ends at once; an answering one stops its work through
  // its CallStop, and its next read or write fails.
  void OnCancel() override {
    if constexpr (kPaced) {
      std::lock_guard lock(mu_);
      cancelled_ = true;
      End(grpc::Status::CANCELLED);
    }
  }
  void OnDone() override {
    ticket_.Release();
    stream_.Release();
    Unref();
  }

 private:
  // Runs `fn` with mu_ held, inside the callback's exception boundary.
  template <class Fn>
  void Guard(Fn&& fn) {
    GuardCallback(
        context_, Session::kName,
        [&] {
          std::lock_guard lock(mu_);
          fn();
        },
        [this](grpc::Status st) {
          std::lock_guard lock(mu_);
          End(std::move(st));
        });
  }

  // The rest run with mu_ held.
  void ReadNext() {
    if (finished_ || reading_ || read_closed_) return;
    reading_ = true;
    this->StartRead(&request_);
  }

  void ReadDone(bool ok) {
    reading_ = false;
    if (finished_) return;
    if (!ok) {  // the client closed its side (or went away)
      read_closed_ = true;
      // A paced session with a duration plays on; without, its next frame ends it.
      if (!kPaced || !started_) End(grpc::Status::OK);
      return;
    }
    if (!started_) {
      if (runners_.start_pool == nullptr) return StartSession();
      runners_.start_pool->Enqueue([this] {
        Guard([&] {
          if (!finished_) StartSession();
        });
      });
      return;
    }
    if constexpr (kPaced) {
      session_->Queue(std::move(request_));
      request_.Clear();
      if (session_->queued() < kMaxQueued) ReadNext();
    } else {
      Answer(session_->Answer(request_, &ClearedOutput()));
    }
  }

  void StartSession() {
    if constexpr (kPaced) {
      if (Status st = session_->Start(call_, request_); !st.ok()) return End(ToGrpcStatus(st));
      started_ = true;
      start_ = std::chrono::steady_clock::now();
      request_.Clear();
      if (!FillNext()) return;
      Write();
      ReadNext();
    } else {
      Answer(session_->Start(call_, request_, &ClearedOutput()));
      started_ = !finished_;
    }
  }

  Output& ClearedOutput() {
    output_.Clear();
    return output_;
  }

  void Answer(const Status& status) {  // answering sessions: output_ holds the answer
    if (!status.ok()) return End(ToGrpcStatus(status));
    Write();
  }

  void WriteDone(bool ok) {
    write_pending_ = false;
    if (end_requested_) return End(end_status_);
    if (!ok) return End(grpc::Status(grpc::StatusCode::CANCELLED, "the client went away"));
    if (finished_) return;
    if constexpr (kPaced) {
      ScheduleNextFrame();
    } else {
      request_.Clear();
      ReadNext();
    }
  }

  void ScheduleNextFrame() {
    if (cancelled_) return End(grpc::Status::CANCELLED);
    // Frame k is due at start + k/fps; a late frame goes at once.
    const auto due =
        start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                     std::chrono::duration<double>(static_cast<double>(session_->frames()) / session_->fps()));
    if (!FillNext()) return;
    refs_.fetch_add(1, std::memory_order_relaxed);
    runners_.scheduler->Schedule(due, [this] {
      {
        std::lock_guard lock(mu_);
        if (cancelled_) End(grpc::Status::CANCELLED);
        if (!finished_) Write();
      }
      Unref();
    });
  }

  // Applies the queued commands and fills output_ with the next frame;
  // false when the session ended instead.
  bool FillNext() {
    if (cancelled_) return End(grpc::Status::CANCELLED), false;
    Status st;
    try {  // the exception boundary of this callback's frame (call_guard.h)
      st = session_->ApplyQueued();
      if (st.ok()) {
        ReadNext();  // reading paused on a full queue resumes
        auto more = session_->NextFrame(read_closed_, &output_);
        if (!more.ok())
          st = more.status();
        else if (!*more)
          return End(grpc::Status::OK), false;
      }
    } catch (...) {
      st = StatusOfCurrentException(context_, Session::kName);
    }
    if (!st.ok()) return End(ToGrpcStatus(st)), false;
    return true;
  }

  void Write() {
    if constexpr (kPaced)
      output_.set_wall_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
    write_pending_ = true;
    write_started_ = std::chrono::steady_clock::now();
    if constexpr (kPaced)
      if (write_timeout_ > 0 && !stall_check_pending_) ScheduleStallCheck(write_started_);
    this->StartWrite(&output_);
  }

  // At `from` + the write timeout: a write blocked since then cancels the call
  // (OnCancel ends it); one still pending but younger is checked again later.
  void ScheduleStallCheck(std::chrono::steady_clock::time_point from) {
    const auto timeout =
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(write_timeout_));
    stall_check_pending_ = true;
    refs_.fetch_add(1, std::memory_order_relaxed);
    runners_.scheduler->Schedule(from + timeout, [this, timeout] {
      bool stalled = false;
      {
        std::lock_guard lock(mu_);
        stall_check_pending_ = false;
        if (!finished_ && write_pending_) {
          if (std::chrono::steady_clock::now() - write_started_ >= timeout)
            stalled = true;
          else
            ScheduleStallCheck(write_started_);
        }
      }
      if (stalled) {
        spdlog::warn("{}: a frame stayed unwritten {} s (the client stopped reading): the call is dropped",
                     Session::kName, write_timeout_);
        context_->TryCancel();  // outside mu_: OnCancel takes it
      }
      Unref();
    });
  }

  // Finishes once; after the write in flight, if any.
  void End(grpc::Status status) noexcept {
    if (finished_) return;
    if (write_pending_) {
      if (!end_requested_) end_status_ = std::move(status);
      end_requested_ = true;
      return;
    }
    finished_ = true;
    session_.reset();
    ticket_.Release();
    this->Finish(std::move(status));
  }

  void Unref() {  // deleted when OnDone has run and no scheduled frame is pending
    if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
  }

  grpc::CallbackServerContext* context_;
  StreamAdmission::Ticket stream_;   // this call's place among the client's streams
  SessionAdmission::Ticket ticket_;  // this session's place
  const SessionRunners runners_;
  std::unique_ptr<Session> session_;
  const double write_timeout_;  // seconds a write may stay blocked; 0 = forever
  CallStop call_;               // the call's deadline and cancellation, for Start

  std::mutex mu_;
  std::atomic<int> refs_{1};  // OnDone's, plus one per scheduled frame
  bool started_ = false, reading_ = false, read_closed_ = false;
  bool write_pending_ = false, cancelled_ = false, finished_ = false, end_requested_ = false;
  bool stall_check_pending_ = false;                     // paced, with a write timeout
  std::chrono::steady_clock::time_point write_started_;  // of the write in flight
  grpc::Status end_status_;
  std::chrono::steady_clock::time_point start_;  // paced: when frame 0 was filled
  typename Session::Request request_;
  Output output_;
};

}  // namespace armature::server
