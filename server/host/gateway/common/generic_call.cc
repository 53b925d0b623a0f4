#include "server/host/gateway/common/generic_call.h"

#include <condition_variable>
#include <deque>
#include <mutex>

namespace armature::server::gateway {

std::string TakeMessage(grpc::ByteBuffer* buffer) {
  std::vector<grpc::Slice> slices;
  (void)buffer->Dump(&slices);
  std::string message;
  for (const auto& s : slices) message.append(reinterpret_cast<const char*>(s.begin()), s.size());
  buffer->Clear();
  return message;
}

struct GenericCall::State {
  std::unique_ptr<grpc::ClientContext> context;
  Reactor* reactor = nullptr;  // valid while `hold` is set

  std::mutex mu;
  std::condition_variable cv;
  std::deque<std::string> queue;
  size_t capacity = 8;
  bool reading = false;  // a read is outstanding
  // The reactor's hold: while set, the consumer may start reads from outside
  // the reactions and the call cannot reach OnDone.
  bool hold = false;
  bool done = false;
  grpc::Status status;

  // The write side: requests wait in `outgoing` (at most `write_capacity`
  // for a producer) until gRPC takes them, one write at a time.
  std::deque<std::string> outgoing;
  size_t write_capacity = 2;
  bool writing = false;        // a write is outstanding
  bool writes_closed = false;  // no more requests will come
  bool cancelled = false;      // no more writes will be started
  bool reads_ended = false;    // the server has answered: writes are of no use
  // The reactor's second hold, for writes started from outside the
  // reactions: dropped by whoever finds no write outstanding and the writes
  // over (closed and sent, failed or cancelled).
  bool write_hold = false;
  bool last_written = false;  // the last request went with StartWriteLast: no WritesDone after it
};

namespace {

std::string TakeFront(std::deque<std::string>& queue) {
  std::string front = std::move(queue.front());
  queue.pop_front();
  return front;
}

// A slice owning `message`'s bytes, without copying them.
grpc::Slice SliceOf(std::string message) {
  auto* owned = new std::string(std::move(message));
  return grpc::Slice(
      owned->data(), owned->size(), [](void* p) { delete static_cast<std::string*>(p); }, owned);
}

}  // namespace

class GenericCall::Reactor final : public grpc::ClientBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer> {
 public:
  enum class WriteStep { kNone, kWrite, kWriteLast, kWritesDone, kRelease };

  explicit Reactor(std::shared_ptr<State> state) : state_(std::move(state)) {}

  void Begin(grpc::GenericStub& stub, const std::string& method) {
    stub.PrepareBidiStreamingCall(state_->context.get(), method, grpc::StubOptions(), this);
    AddHold();
    AddHold();
    std::string message;
    WriteStep step;
    {
      std::lock_guard lock(state_->mu);
      state_->hold = true;
      state_->write_hold = true;
      state_->reading = true;
      step = ClaimWriteStep(*state_, &message);
    }
    StartRead(&read_buf_);
    TakeWriteStep(step, std::move(message));
    StartCall();
  }

  // Only the consumer calls this, and only while it holds the hold.
  void ReadAgain() { StartRead(&read_buf_); }
  void Release() { RemoveHold(); }

  // The next write step, claimed under state.mu: a claimed write or the hold's
  // release is then this caller's alone to take (TakeWriteStep, outside the
  // lock), so the reactor outlives it.
  static WriteStep ClaimWriteStep(State& s, std::string* message) {
    if (s.writing || !s.write_hold) return WriteStep::kNone;
    if (s.cancelled) {
      s.write_hold = false;
      return WriteStep::kRelease;
    }
    if (!s.outgoing.empty()) {
      s.writing = true;
      *message = TakeFront(s.outgoing);
      s.cv.notify_all();  // room for the producer
      // The last request of a closed call goes as StartWriteLast, as unary
      // calls always did: a separate WritesDone after the call's answer kept
      // each call's arena until shutdown (about 10 KB per gateway call).
      if (s.outgoing.empty() && s.writes_closed) {
        s.last_written = true;
        return WriteStep::kWriteLast;
      }
      return WriteStep::kWrite;
    }
    if (!s.writes_closed) return WriteStep::kNone;
    s.write_hold = false;
    return s.last_written ? WriteStep::kRelease : WriteStep::kWritesDone;
  }

  void TakeWriteStep(WriteStep step, std::string message) {
    switch (step) {
      case WriteStep::kNone: return;
      case WriteStep::kWrite:
      case WriteStep::kWriteLast: {
        grpc::Slice slice = SliceOf(std::move(message));  // gRPC owns the bytes now
        write_buf_ = grpc::ByteBuffer(&slice, 1);
        if (step == WriteStep::kWriteLast) return StartWriteLast(&write_buf_, grpc::WriteOptions());
        return StartWrite(&write_buf_);
      }
      case WriteStep::kWritesDone: StartWritesDone(); return RemoveHold();
      case WriteStep::kRelease: return RemoveHold();
    }
  }

  void OnWriteDone(bool ok) override {
    std::string message;
    WriteStep step;
    {
      std::lock_guard lock(state_->mu);
      state_->writing = false;
      if (!ok) state_->cancelled = true;  // the call is over: no more writes
      step = ClaimWriteStep(*state_, &message);
      state_->cv.notify_all();
    }
    TakeWriteStep(step, std::move(message));
  }

  void OnReadDone(bool ok) override {
    bool again = false, release = false;
    {
      std::lock_guard lock(state_->mu);
      state_->reading = false;
      if (ok) {
        state_->queue.push_back(TakeMessage(&read_buf_));
        if (state_->queue.size() < state_->capacity) again = state_->reading = true;
      } else {
        state_->reads_ended = true;
        if (state_->hold) {  // no more responses: let the call finish
          state_->hold = false;
          release = true;
        }
      }
      state_->cv.notify_all();
    }
    if (again) StartRead(&read_buf_);
    if (release) RemoveHold();
  }

  void OnDone(const grpc::Status& status) override {
    {
      std::lock_guard lock(state_->mu);
      state_->done = true;
      state_->status = status;
      state_->reactor = nullptr;
      state_->cv.notify_all();
    }
    delete this;
  }

 private:
  std::shared_ptr<State> state_;
  grpc::ByteBuffer write_buf_;
  grpc::ByteBuffer read_buf_;
};

std::unique_ptr<GenericCall> GenericCall::Start(grpc::GenericStub& stub, const std::string& method,
                                                std::unique_ptr<grpc::ClientContext> context,
                                                std::vector<std::string> requests, size_t queue_capacity) {
  auto state = std::make_shared<State>();
  state->context = std::move(context);
  state->capacity = std::max<size_t>(1, queue_capacity);
  for (std::string& r : requests) state->outgoing.push_back(std::move(r));
  state->writes_closed = true;
  auto* reactor = new Reactor(state);
  state->reactor = reactor;
  std::unique_ptr<GenericCall> call(new GenericCall(state));
  reactor->Begin(stub, method);
  return call;
}

std::unique_ptr<GenericCall> GenericCall::StartWriting(grpc::GenericStub& stub, const std::string& method,
                                                       std::unique_ptr<grpc::ClientContext> context,
                                                       size_t write_capacity) {
  auto state = std::make_shared<State>();
  state->context = std::move(context);
  state->capacity = 1;  // one response: a client-streaming call
  state->write_capacity = std::max<size_t>(1, write_capacity);
  auto* reactor = new Reactor(state);
  state->reactor = reactor;
  std::unique_ptr<GenericCall> call(new GenericCall(state));
  reactor->Begin(stub, method);
  return call;
}

bool GenericCall::Write(std::string request) {
  std::string message;
  Reactor::WriteStep step;
  Reactor* reactor = nullptr;
  {
    std::unique_lock lock(state_->mu);
    const auto over = [&] { return state_->cancelled || state_->done || state_->reads_ended || !state_->write_hold; };
    state_->cv.wait(lock, [&] { return over() || state_->outgoing.size() < state_->write_capacity; });
    if (over() || state_->writes_closed) return false;
    state_->outgoing.push_back(std::move(request));
    step = Reactor::ClaimWriteStep(*state_, &message);
    reactor = state_->reactor;
  }
  reactor->TakeWriteStep(step, std::move(message));
  return true;
}

void GenericCall::CloseWrites() {
  std::string message;
  Reactor::WriteStep step;
  Reactor* reactor = nullptr;
  {
    std::lock_guard lock(state_->mu);
    state_->writes_closed = true;
    step = Reactor::ClaimWriteStep(*state_, &message);
    reactor = state_->reactor;
  }
  if (step != Reactor::WriteStep::kNone) reactor->TakeWriteStep(step, std::move(message));
}

GenericCall::~GenericCall() { Cancel(); }

GenericCall::Next GenericCall::Read(std::string* out, std::chrono::milliseconds timeout) {
  {
    std::unique_lock lock(state_->mu);
    const auto ready = [&] { return !state_->queue.empty() || state_->done; };
    if (timeout == kForever)
      state_->cv.wait(lock, ready);
    else
      state_->cv.wait_for(lock, timeout, ready);
    if (state_->queue.empty()) return state_->done ? Next::kEnd : Next::kTimeout;
    *out = std::move(state_->queue.front());
    state_->queue.pop_front();
  }
  ResumeReading();
  return Next::kMessage;
}

grpc::Status GenericCall::Drain(std::vector<std::string>* responses) {
  std::string message;
  while (Read(&message) == Next::kMessage) responses->push_back(std::move(message));
  return status();
}

grpc::Status GenericCall::status() const {
  std::lock_guard lock(state_->mu);
  return state_->status;
}

void GenericCall::ResumeReading() {
  Reactor* reactor = nullptr;
  {
    std::lock_guard lock(state_->mu);
    if (state_->reading || !state_->hold || state_->queue.size() >= state_->capacity) return;
    state_->reading = true;
    reactor = state_->reactor;
  }
  // Outside the lock: the read may complete inline and its reaction takes it.
  reactor->ReadAgain();
}

void GenericCall::Cancel() {
  Reactor* release = nullptr;
  Reactor* reactor = nullptr;
  std::string unused;
  Reactor::WriteStep write_step;
  {
    std::lock_guard lock(state_->mu);
    if (state_->done) return;
    // With no read outstanding nothing else would drop the hold.
    if (state_->hold && !state_->reading) {
      state_->hold = false;
      release = state_->reactor;
    }
    // Likewise the write hold with no write outstanding.
    state_->cancelled = true;
    write_step = Reactor::ClaimWriteStep(*state_, &unused);
    reactor = state_->reactor;
    state_->cv.notify_all();  // a producer waiting for room
  }
  state_->context->TryCancel();
  if (write_step != Reactor::WriteStep::kNone) reactor->TakeWriteStep(write_step, {});
  if (release) release->Release();
}

}  // namespace armature::server::gateway
