// A program outside the Armature tree using the installed client library: it
// builds a request and sees a clear UNAVAILABLE error from a port with no server.
#include <iostream>

#include <armature/client.h>

int main() {
  armature::client::ClientOptions options;
  options.target = "127.0.0.1:1";
  options.timeout = std::chrono::seconds(2);
  armature::client::Client client(options);
  armature::v1::EvaluateClipRequest request;
  request.set_clip("walk");
  request.add_times(0.5);
  try {
    client.EvaluateClip(request);
  } catch (const armature::client::ClientError& e) {
    std::cout << "got " << armature::client::StatusCodeName(e.code()) << ": " << e.what() << "\n";
    return e.code() == grpc::StatusCode::UNAVAILABLE ? 0 : 1;
  }
  std::cerr << "expected an error\n";
  return 1;
}
