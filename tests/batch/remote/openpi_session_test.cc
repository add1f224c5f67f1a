// The client against policy_server.py, an openpi-style server on Debian's python3-websockets
// (legacy API) and python3-msgpack: a counterpart whose websocket and msgpack code we did not
// write. Loopback only; every wait is bounded.
#include "batch/remote/openpi_session.h"

#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <iostream>
#include <numeric>
#include <optional>
#include <thread>

#include "batch/remote/health_probe.h"
#include "batch/remote/msgpack_encoder.h"
#include "batch/remote/openpi_reply.h"
#include "batch/remote/remote_error.h"
#include "tests/batch/remote/golden_values.h"
#include "tests/batch/remote/policy_server_process.h"
#include "tests/batch/remote/test_scripts.h"

namespace tavis::batch::remote {
namespace {

using std::chrono::milliseconds;
using testing::StrMap;

constexpr int kHorizon = 10;
constexpr int kActionDim = 7;

// policy_server.py answering kHorizon x kActionDim chunks.
class PolicyServer : public testing::PolicyServerProcess {
 public:
  explicit PolicyServer(std::vector<std::string> extra_args = {}, bool wait_ready = true)
      : PolicyServerProcess(WithShape(std::move(extra_args)), wait_ready) {}

 private:
  static std::vector<std::string> WithShape(std::vector<std::string> extra) {
    extra.insert(extra.begin(), {"--horizon", std::to_string(kHorizon), "--action-dim", std::to_string(kActionDim)});
    return extra;
  }
};

struct TestObservation {
  std::vector<NdArray> images;
  std::vector<float> state;
  std::string prompt;

  Value ToValue(std::vector<std::pair<std::string, Value>> extra = {}) const {
    std::vector<std::pair<std::string, Value>> entries;
    for (std::size_t i = 0; i < images.size(); ++i)
      entries.emplace_back("observation/image_" + std::to_string(i), images[i]);
    entries.emplace_back("observation/state", MakeFloat32Array({static_cast<std::int64_t>(state.size())}, state));
    entries.emplace_back("prompt", prompt);
    for (auto& entry : extra) entries.push_back(std::move(entry));
    return StrMap(std::move(entries));
  }

  std::uint64_t ImageSum() const {
    std::uint64_t sum = 0;
    for (const NdArray& image : images) sum = std::accumulate(image.data.begin(), image.data.end(), sum);
    return sum;
  }

  // policy_server.py's function, in the same float64 operation order.
  std::vector<double> ExpectedActions() const {
    const double offset = static_cast<double>(ImageSum() % 1024) / 8 + static_cast<double>(prompt.size()) * 0.25;
    std::vector<double> actions;
    for (int t = 0; t < kHorizon; ++t) {
      for (int d = 0; d < kActionDim; ++d)
        actions.push_back(static_cast<double>(state[d % state.size()]) * (t + 1) + offset + d);
    }
    return actions;
  }
};

TestObservation LiberoLikeObservation(int images, std::int64_t height, std::int64_t width, int seed) {
  TestObservation observation;
  for (int i = 0; i < images; ++i)
    observation.images.push_back(testing::PatternImage({height, width, 3}, 200 + seed + i));
  observation.state = {0.5F, -1.25F, 2.0F + static_cast<float>(seed), 0.0F, 1.0F, -3.5F, 0.04F, 0.04F};
  observation.prompt = "pick up the red cube";
  return observation;
}

OpenpiSession Connect(const PolicyServer& server) {
  OpenpiSessionOptions options;
  options.url = server.address();
  options.connect_timeout = milliseconds(10'000);
  options.reply_timeout = milliseconds(30'000);
  return OpenpiSession(options);
}

TEST(OpenpiSession, ReadsTheMetadataFirst) {
  PolicyServer server;
  OpenpiSession session = Connect(server);
  const Value& metadata = session.metadata();
  EXPECT_EQ(metadata.Find("action_horizon")->as<std::int64_t>("action_horizon"), kHorizon);
  EXPECT_EQ(metadata.Find("server")->as<std::string>("server"), "tavis test policy");
  EXPECT_TRUE(*metadata.Find("reset_pose") == (Value::Array{0, -1.5, 1.5, 0, 0, 0}));
}

TEST(OpenpiSession, ActionChunksEqualTheServersFunctionInBothDtypes) {
  PolicyServer server;
  OpenpiSession session = Connect(server);
  for (int request = 0; request < 3; ++request) {
    const TestObservation observation = LiberoLikeObservation(2, 224, 224, request);
    const bool single = request == 1;
    const InferResult result = session.Infer(observation.ToValue({{"test/actions_dtype", single ? "<f4" : "<f8"}}));
    const ActionChunk chunk = ReadActionChunk(result.reply);
    EXPECT_EQ(chunk.horizon, kHorizon);
    EXPECT_EQ(chunk.dim, kActionDim);
    EXPECT_EQ(chunk.dtype, single ? "<f4" : "<f8");
    std::vector<double> expected = observation.ExpectedActions();
    if (single) {
      for (double& value : expected) value = static_cast<double>(static_cast<float>(value));
    }
    EXPECT_EQ(chunk.values, expected) << "request " << request;
    EXPECT_EQ(result.reply.Find("image_sum")->as<std::int64_t>("image_sum"),
              static_cast<std::int64_t>(observation.ImageSum()));
    EXPECT_EQ(result.reply.Find("request")->as<std::int64_t>("request"), request);
    EXPECT_FALSE(result.reconnected);
    EXPECT_GT(result.round_trip_ms, 0.0);

    const ReplyTimings timings = ReadReplyTimings(result.reply);
    ASSERT_TRUE(timings.server_infer_ms.has_value());
    ASSERT_TRUE(timings.policy_infer_ms.has_value());
    EXPECT_GE(*timings.server_infer_ms, 0.0);
    EXPECT_EQ(timings.server_prev_total_ms.has_value(), request > 0) << "prev_total_ms appears from the 2nd request on";
  }
}

TEST(OpenpiSession, CarriesMessagesOverOneMebibyte) {
  PolicyServer server;
  OpenpiSession session = Connect(server);
  const TestObservation observation = LiberoLikeObservation(4, 480, 640, 7);
  const Value request = observation.ToValue();
  const Clock::time_point encode_start = Clock::now();
  const std::size_t request_bytes = EncodeMsgpack(request).size();
  const double encode_ms = std::chrono::duration<double, std::milli>(Clock::now() - encode_start).count();
  ASSERT_GT(request_bytes, 3U * (1U << 20));
  constexpr int kRepeats = 10;
  double total_ms = 0;
  double server_ms = 0;
  for (int repeat = 0; repeat < kRepeats; ++repeat) {
    const InferResult result = session.Infer(request);
    server_ms += ReadReplyTimings(result.reply).server_infer_ms.value_or(0.0);
    EXPECT_EQ(ReadActionChunk(result.reply).values, observation.ExpectedActions());
    EXPECT_EQ(result.reply.Find("image_sum")->as<std::int64_t>("image_sum"),
              static_cast<std::int64_t>(observation.ImageSum()));
    total_ms += result.round_trip_ms;
  }
  std::cout << "[ measure  ] four 640x480x3 images, " << request_bytes << " bytes per request: mean round trip "
            << total_ms / kRepeats << " ms over " << kRepeats << " requests on loopback (server's infer_ms "
            << server_ms / kRepeats << " ms; our msgpack encoding " << encode_ms << " ms)\n";
}

TEST(OpenpiSession, ServerErrorSurfacesTheTracebackAndTheSessionRecovers) {
  PolicyServer server;
  OpenpiSession session = Connect(server);
  const TestObservation observation = LiberoLikeObservation(1, 8, 8, 0);
  try {
    session.Infer(observation.ToValue({{"test/raise", "gripper exploded"}}));
    FAIL() << "no error";
  } catch (const PolicyServerError& error) {
    EXPECT_EQ(error.close_code(), 1011);
    EXPECT_NE(error.traceback().find("Traceback (most recent call last)"), std::string::npos) << error.traceback();
    EXPECT_NE(error.traceback().find("RuntimeError: test policy asked to fail: gripper exploded"), std::string::npos);
    const std::string message = error.what();
    EXPECT_NE(
        message.find("policy server error (close 1011: Internal server error. Traceback included in previous frame.)"),
        std::string::npos)
        << message;
  }
  const InferResult result = session.Infer(observation.ToValue());
  EXPECT_TRUE(result.reconnected);
  EXPECT_EQ(ReadActionChunk(result.reply).values, observation.ExpectedActions());
}

// A runaway reply is refused from its frame header (nothing of it is buffered), as a malformed
// reply that ends only its episode; the session reconnects for the next request.
TEST(OpenpiSession, ReplyOverTheSizeLimitIsMalformedAndTheNextRequestWorks) {
  PolicyServer server;
  OpenpiSessionOptions options;
  options.url = server.address();
  options.reply_timeout = milliseconds(30'000);
  options.max_reply_bytes = 1 << 20;
  OpenpiSession session(options);
  const TestObservation observation = LiberoLikeObservation(1, 8, 8, 0);
  try {
    session.Infer(observation.ToValue({{"test/pad_bytes", std::int64_t{4} << 20}}));
    FAIL() << "a 4 MiB reply passed a 1 MiB limit";
  } catch (const MalformedReply& error) {
    EXPECT_NE(std::string(error.what()).find("over the limit of 1048576 bytes"), std::string::npos) << error.what();
  }
  const InferResult result = session.Infer(observation.ToValue());
  EXPECT_TRUE(result.reconnected);
  EXPECT_EQ(ReadActionChunk(result.reply).values, observation.ExpectedActions());
}

TEST(OpenpiSession, DefaultReplyLimitHoldsTheLargestLegalChunk) {
  EXPECT_GE(kDefaultMaxReplyBytes, 100'000u * 19u * 8u + 4096u);
  EXPECT_LE(kDefaultMaxReplyBytes, std::uint64_t{64} << 20) << "a limit that lets a runaway server fill memory";
}

// Broken msgpack-numpy arrays are the reply's fault, not the connection's: each is a
// MalformedReply naming the defect, and the same connection answers the next request.
TEST(OpenpiSession, BrokenNdarrayRepliesAreMalformedAndTheSessionGoesOn) {
  PolicyServer server;
  OpenpiSession session = Connect(server);
  const TestObservation observation = LiberoLikeObservation(1, 8, 8, 0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"short_data", "has 8"}, {"huge_shape", "2^62"}, {"bad_dtype", "zz9"}};
  for (const auto& [broken, named] : cases) {
    try {
      session.Infer(observation.ToValue({{"test/broken_actions", broken}}));
      ADD_FAILURE() << broken << " passed";
    } catch (const MalformedReply& error) {
      EXPECT_NE(std::string(error.what()).find(named), std::string::npos) << broken << ": " << error.what();
    }
    const InferResult result = session.Infer(observation.ToValue());
    EXPECT_FALSE(result.reconnected) << broken;
    EXPECT_EQ(ReadActionChunk(result.reply).values, observation.ExpectedActions()) << broken;
  }
}

TEST(OpenpiSession, ReconnectsAfterTheServerClosesAndReadsTheMetadataAgain) {
  PolicyServer server;
  OpenpiSession session = Connect(server);
  const TestObservation observation = LiberoLikeObservation(1, 16, 16, 3);
  const InferResult first = session.Infer(observation.ToValue({{"test/close_after_reply", true}}));
  EXPECT_EQ(first.reply.Find("connection")->as<std::int64_t>("connection"), 1);
  const InferResult second = session.Infer(observation.ToValue());
  EXPECT_TRUE(second.reconnected);
  EXPECT_EQ(second.reply.Find("connection")->as<std::int64_t>("connection"), 2);
  EXPECT_EQ(second.reply.Find("request")->as<std::int64_t>("request"), 0);
  EXPECT_EQ(session.reconnects(), 1);
  EXPECT_EQ(session.metadata().Find("action_dim")->as<std::int64_t>("action_dim"), kActionDim);
}

TEST(OpenpiSession, AnsweredPingsKeepTheConnectionThroughAPause) {
  PolicyServer server({"--ping-interval", "0.2", "--ping-timeout", "1.5"});
  OpenpiSession session = Connect(server);
  const TestObservation observation = LiberoLikeObservation(1, 8, 8, 1);
  session.Infer(observation.ToValue());
  for (int pause = 0; pause < 8; ++pause) {  // 4 s busy: unanswered pings would time out at ~1.7 s
    std::this_thread::sleep_for(milliseconds(500));
    session.ServiceKeepalive();
  }
  const InferResult result = session.Infer(observation.ToValue());
  EXPECT_FALSE(result.reconnected);
  EXPECT_EQ(result.reply.Find("connection")->as<std::int64_t>("connection"), 1);
  EXPECT_EQ(session.reconnects(), 0);
}

TEST(OpenpiSession, ReconnectsWhenTheKeepaliveDroppedAStalledClient) {
  PolicyServer server({"--ping-interval", "0.2", "--ping-timeout", "0.3"});
  OpenpiSession session = Connect(server);
  const TestObservation observation = LiberoLikeObservation(1, 8, 8, 2);
  session.Infer(observation.ToValue());
  std::this_thread::sleep_for(milliseconds(1500));  // no reads: the server's ping goes unanswered
  const InferResult result = session.Infer(observation.ToValue());
  EXPECT_TRUE(result.reconnected);
  EXPECT_EQ(result.reply.Find("connection")->as<std::int64_t>("connection"), 2);
  EXPECT_EQ(ReadActionChunk(result.reply).values, observation.ExpectedActions());
}

TEST(OpenpiSession, ReplyTimeoutIsBoundedAndTheLateReplyIsNotTakenForTheNext) {
  PolicyServer server;
  OpenpiSessionOptions options;
  options.url = server.address();
  options.reply_timeout = milliseconds(300);
  OpenpiSession session(options);
  const TestObservation slow = LiberoLikeObservation(1, 8, 8, 4);
  const auto start = Clock::now();
  EXPECT_THROW(session.Infer(slow.ToValue({{"test/delay_s", 1.0}})), RemoteTimeout);
  EXPECT_LT(Clock::now() - start, milliseconds(900));
  const TestObservation next = LiberoLikeObservation(1, 8, 8, 5);
  const InferResult result = session.Infer(next.ToValue());
  EXPECT_TRUE(result.reconnected);
  EXPECT_EQ(ReadActionChunk(result.reply).values, next.ExpectedActions());
}

TEST(OpenpiSession, ServerDyingMidSessionIsAClearError) {
  std::optional<PolicyServer> server(std::in_place);
  OpenpiSession session = Connect(*server);
  const TestObservation observation = LiberoLikeObservation(1, 8, 8, 6);
  session.Infer(observation.ToValue());
  const std::string address = server->address().substr(5);  // without "ws://"
  server.reset();
  try {
    session.Infer(observation.ToValue());
    FAIL() << "no error";
  } catch (const ConnectFailed& error) {
    EXPECT_STREQ(error.what(), ("cannot connect to policy server " + address + ": Connection refused").c_str());
  }
}

TEST(HealthProbe, WaitsForAServerThatIsStillStarting) {
  const auto start = Clock::now();
  PolicyServer server({"--startup-delay", "1.0"}, /*wait_ready=*/false);
  WaitForHealthz(server.url(), milliseconds(20'000));  // one bounded wait through refused connections
  EXPECT_GE(Clock::now() - start, milliseconds(900));
  EXPECT_NO_THROW(Connect(server));
}

TEST(HealthProbe, UnreachableServerFailsClearlyAfterTheBoundedWait) {
  const int port = testing::FreeLoopbackPort();
  const auto start = Clock::now();
  try {
    WaitForHealthz({"127.0.0.1", port, "/"}, milliseconds(600));
    FAIL() << "no error";
  } catch (const RemoteTimeout& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("policy server 127.0.0.1:" + std::to_string(port) + " not ready"), std::string::npos)
        << message;
    EXPECT_NE(message.find("Connection refused"), std::string::npos) << message;
  }
  const auto waited = Clock::now() - start;
  EXPECT_GE(waited, milliseconds(600));
  EXPECT_LT(waited, milliseconds(3000));

  OpenpiSessionOptions options;
  options.url = "ws://127.0.0.1:" + std::to_string(port);
  try {
    OpenpiSession session(options);
    FAIL() << "no error";
  } catch (const ConnectFailed& error) {
    EXPECT_STREQ(
        error.what(),
        ("cannot connect to policy server 127.0.0.1:" + std::to_string(port) + ": Connection refused").c_str());
  }
}

TEST(OpenpiSession, SilentServerTimesOutDuringTheHandshake) {
  // A socket that listens but never answers: the kernel completes the TCP connect, nothing more.
  const int listener = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  ASSERT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(listen(listener, 4), 0);
  ASSERT_EQ(getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length), 0);
  OpenpiSessionOptions options;
  options.url = "ws://127.0.0.1:" + std::to_string(ntohs(address.sin_port));
  options.connect_timeout = milliseconds(400);
  const auto start = Clock::now();
  EXPECT_THROW(OpenpiSession session(options), RemoteTimeout);
  EXPECT_LT(Clock::now() - start, milliseconds(2000));
  close(listener);
}

}  // namespace
}  // namespace tavis::batch::remote
