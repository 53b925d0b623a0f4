#include "server/host/gateway/common/bidi_call.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <deque>
#include <mutex>

#include "server/host/gateway/common/generic_call.h"  // TakeMessage

namespace armature::server::gateway {

// The reactor lives until OnDone. Two holds keep OnDone away while the
// consumer may still start operations from outside the reactions: the read
// hold (dropped when the responses end or the call is cancelled) and the
// write hold (dropped once the half-close is sent, or when writing stops).
struct BidiCall::State {
  std::unique_ptr<grpc::ClientContext> context;
  Reactor* reactor = nullptr;
  int wake = -1;

  mutable std::mutex mu;
  // Reads.
  std::deque<std::string> responses;
  size_t capacity = 8;
  bool reading = false;
  bool read_hold = false;
  // Writes.
  std::deque<std::string> requests;
  bool writing = false;
  bool write_hold = false;
  bool half_close = false;  // asked for by the consumer
  bool write_failed = false;
  // The call.
  bool cancelled = false;
  bool done = false;
  grpc::Status status;

  ~State() {
    if (wake >= 0) ::close(wake);
  }
  void Wake() const {
    const uint64_t one = 1;
    (void)!::write(wake, &one, sizeof(one));
  }
};

class BidiCall::Reactor final : public grpc::ClientBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer> {
 public:
  explicit Reactor(std::shared_ptr<State> state) : state_(std::move(state)) {}

  void Begin(grpc::GenericStub& stub, const std::string& method) {
    stub.PrepareBidiStreamingCall(state_->context.get(), method, grpc::StubOptions(), this);
    AddMultipleHolds(2);
    state_->read_hold = state_->write_hold = true;
    state_->reading = true;
    StartRead(&read_buf_);
    StartCall();
  }

  // What the consumer may start, decided under the lock and started outside
  // it (a start may complete inline, and its reaction takes the lock).
  struct Actions {
    bool read = false;
    std::string* write = nullptr;
    bool writes_done = false;
    bool release_read = false;
    bool release_write = false;
  };
  Actions Decide() {  // state_->mu held
    State& s = *state_;
    Actions a;
    if (s.read_hold && s.cancelled && !s.reading) {
      s.read_hold = false;
      a.release_read = true;
    }
    if (s.read_hold && !s.reading && s.responses.size() < s.capacity) a.read = s.reading = true;
    if (s.write_hold && !s.writing) {
      const bool stop = s.cancelled || s.write_failed || !s.read_hold;
      if (!stop && !s.requests.empty()) {
        write_msg_ = std::move(s.requests.front());
        s.requests.pop_front();
        s.writing = true;
        a.write = &write_msg_;
      } else if (stop || s.half_close) {
        a.writes_done = !stop;
        s.write_hold = false;
        a.release_write = true;
      }
    }
    return a;
  }
  void Run(Actions a) {
    if (a.read) StartRead(&read_buf_);
    if (a.write) {
      grpc::Slice slice(*a.write);
      std::string().swap(*a.write);
      write_buf_ = grpc::ByteBuffer(&slice, 1);
      StartWrite(&write_buf_);
    }
    if (a.writes_done) StartWritesDone();
    if (a.release_write) RemoveHold();
    if (a.release_read) RemoveHold();
  }

  void OnWriteDone(bool ok) override {
    Actions a;
    {
      std::lock_guard lock(state_->mu);
      state_->writing = false;
      if (!ok) state_->write_failed = true;
      a = Decide();
    }
    state_->Wake();
    Run(a);
  }

  void OnReadDone(bool ok) override {
    Actions a;
    {
      std::lock_guard lock(state_->mu);
      state_->reading = false;
      if (ok) {
        state_->responses.push_back(TakeMessage(&read_buf_));
      } else if (state_->read_hold) {  // no more responses: let the call finish
        state_->read_hold = false;
        a.release_read = true;
      }
      Actions more = Decide();
      more.release_read |= a.release_read;
      a = more;
    }
    state_->Wake();
    Run(a);
  }

  void OnDone(const grpc::Status& status) override {
    {
      std::lock_guard lock(state_->mu);
      state_->done = true;
      state_->status = status;
      state_->reactor = nullptr;
      state_->Wake();
    }
    delete this;
  }

 private:
  std::shared_ptr<State> state_;
  std::string write_msg_;
  grpc::ByteBuffer write_buf_;
  grpc::ByteBuffer read_buf_;
};

std::unique_ptr<BidiCall> BidiCall::Start(grpc::GenericStub& stub, const std::string& method,
                                          std::unique_ptr<grpc::ClientContext> context, size_t queue_capacity) {
  auto state = std::make_shared<State>();
  state->context = std::move(context);
  state->capacity = std::max<size_t>(1, queue_capacity);
  state->wake = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  auto* reactor = new Reactor(state);
  state->reactor = reactor;
  std::unique_ptr<BidiCall> call(new BidiCall(state));
  reactor->Begin(stub, method);
  return call;
}

BidiCall::~BidiCall() { Cancel(); }

void BidiCall::Pump() {
  Reactor::Actions a;
  Reactor* reactor = nullptr;
  {
    std::lock_guard lock(state_->mu);
    reactor = state_->reactor;
    if (!reactor) return;
    a = reactor->Decide();
  }
  if (!a.read && !a.write && !a.writes_done && !a.release_read && !a.release_write) return;
  // Until Run drops them, the holds these actions stand on keep the reactor alive.
  reactor->Run(a);
}

bool BidiCall::Write(std::string message) {
  {
    std::lock_guard lock(state_->mu);
    if (!state_->write_hold || state_->half_close || state_->cancelled || state_->write_failed) return false;
    state_->requests.push_back(std::move(message));
  }
  Pump();
  return true;
}

size_t BidiCall::pending_writes() const {
  std::lock_guard lock(state_->mu);
  return state_->requests.size() + (state_->writing ? 1 : 0);
}

void BidiCall::WritesDone() {
  {
    std::lock_guard lock(state_->mu);
    state_->half_close = true;
  }
  Pump();
}

BidiCall::Next BidiCall::Read(std::string* out) {
  {
    std::lock_guard lock(state_->mu);
    if (state_->responses.empty()) return state_->done ? Next::kEnd : Next::kNone;
    *out = std::move(state_->responses.front());
    state_->responses.pop_front();
  }
  Pump();  // room in the queue: read on
  return Next::kMessage;
}

grpc::Status BidiCall::status() const {
  std::lock_guard lock(state_->mu);
  return state_->status;
}

int BidiCall::wake_fd() const { return state_->wake; }

void BidiCall::ClearWake() {
  uint64_t count;
  (void)!::read(state_->wake, &count, sizeof(count));
}

void BidiCall::Cancel() {
  {
    std::lock_guard lock(state_->mu);
    if (state_->done || state_->cancelled) return;
    state_->cancelled = true;
    state_->requests.clear();
  }
  state_->context->TryCancel();
  Pump();  // drops the holds no operation in flight will drop
}

}  // namespace armature::server::gateway
