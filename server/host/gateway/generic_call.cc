#include "server/host/gateway/generic_call.h"

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
};

class GenericCall::Reactor final : public grpc::ClientBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer> {
 public:
  Reactor(std::shared_ptr<State> state, std::vector<std::string> requests)
      : state_(std::move(state)), requests_(std::move(requests)) {}

  void Begin(grpc::GenericStub& stub, const std::string& method) {
    stub.PrepareBidiStreamingCall(state_->context.get(), method, grpc::StubOptions(), this);
    AddHold();
    state_->hold = true;
    state_->reading = true;
    StartRead(&read_buf_);
    WriteNext();
    StartCall();
  }

  // Only the consumer calls this, and only while it holds the hold.
  void ReadAgain() { StartRead(&read_buf_); }
  void Release() { RemoveHold(); }

  void OnWriteDone(bool ok) override {
    if (ok) WriteNext();
  }

  void OnReadDone(bool ok) override {
    bool again = false, release = false;
    {
      std::lock_guard lock(state_->mu);
      state_->reading = false;
      if (ok) {
        state_->queue.push_back(TakeMessage(&read_buf_));
        if (state_->queue.size() < state_->capacity) again = state_->reading = true;
      } else if (state_->hold) {  // no more responses: let the call finish
        state_->hold = false;
        release = true;
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
  void WriteNext() {
    if (requests_.empty()) return StartWritesDone();
    if (next_ == requests_.size()) return;
    grpc::Slice slice(requests_[next_]);
    std::string().swap(requests_[next_]);  // gRPC has its own copy now
    write_buf_ = grpc::ByteBuffer(&slice, 1);
    if (++next_ == requests_.size())
      StartWriteLast(&write_buf_, grpc::WriteOptions());
    else
      StartWrite(&write_buf_);
  }

  std::shared_ptr<State> state_;
  std::vector<std::string> requests_;
  size_t next_ = 0;
  grpc::ByteBuffer write_buf_;
  grpc::ByteBuffer read_buf_;
};

std::unique_ptr<GenericCall> GenericCall::Start(grpc::GenericStub& stub, const std::string& method,
                                                std::unique_ptr<grpc::ClientContext> context,
                                                std::vector<std::string> requests, size_t queue_capacity) {
  auto state = std::make_shared<State>();
  state->context = std::move(context);
  state->capacity = std::max<size_t>(1, queue_capacity);
  auto* reactor = new Reactor(state, std::move(requests));
  state->reactor = reactor;
  std::unique_ptr<GenericCall> call(new GenericCall(state));
  reactor->Begin(stub, method);
  return call;
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
  {
    std::lock_guard lock(state_->mu);
    if (state_->done) return;
    // With no read outstanding nothing else would drop the hold.
    if (state_->hold && !state_->reading) {
      state_->hold = false;
      release = state_->reactor;
    }
  }
  state_->context->TryCancel();
  if (release) release->Release();
}

}  // namespace armature::server::gateway
