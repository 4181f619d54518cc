// semfuse_dds_echo <domain> <topic prefix>: republishes every sample of every wire type from
// "<prefix>/in/<type>" on "<prefix>/out/<type>", decoded and re-encoded by Cyclone on the way.
// It is the second process of the round-trip test; it ends on SIGTERM, when its parent dies,
// or after a hard limit, so a crashed test never leaves it behind. It ends cleanly (deleting its
// participant) so that peers forget its endpoints at once instead of at lease expiry.
#include <sys/prctl.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"
#include "wire_types.hpp"

namespace {

using namespace semfuse::dds;

constexpr dds_duration_t kLifetime = DDS_SECS(300);
// How often the loop looks at the stop flag; a signal handler may not touch DDS itself.
constexpr dds_duration_t kStopPoll = DDS_MSECS(50);

volatile std::sig_atomic_t stop_requested = 0;
void requestStop(int) { stop_requested = 1; }

class Echo {
 public:
  virtual ~Echo() = default;
  virtual dds_entity_t condition() const = 0;
  virtual void pump() = 0;
};

template <class T>
class TypedEcho final : public Echo {
 public:
  TypedEcho(const Participant& participant, const std::string& prefix, const Qos& qos)
      : in_topic_(participant, prefix + "/in/" + testing::topicSuffix<T>()),
        out_topic_(participant, prefix + "/out/" + testing::topicSuffix<T>()),
        reader_(in_topic_, qos),
        writer_(out_topic_, qos),
        data_(reader_.handle()) {}

  dds_entity_t condition() const override { return data_.handle(); }
  void pump() override {
    while (auto sample = reader_.take()) {
      if (semfuse::Status s = writer_.write(**sample); !s) {
        std::fprintf(stderr, "echo %s: %s\n", writer_.topicName().c_str(), s.error().c_str());
      }
    }
  }

 private:
  Topic<T> in_topic_;
  Topic<T> out_topic_;
  Reader<T> reader_;
  Writer<T> writer_;
  ReadCondition data_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <domain> <topic prefix>\n", argv[0]);
    return 2;
  }
  std::signal(SIGTERM, requestStop);
  std::signal(SIGINT, requestStop);
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  try {
    const Participant participant(static_cast<dds_domainid_t>(std::atoi(argv[1])));
    const std::string prefix = argv[2];
    const Qos qos = Qos().reliable(qos::kMaxBlockingTime).keepAll().transientLocal();
    std::vector<std::unique_ptr<Echo>> echoes;
    semfuse::dds::testing::forEachWireType([&](auto tag) {
      using T = typename decltype(tag)::type;
      echoes.push_back(std::make_unique<TypedEcho<T>>(participant, prefix, qos));
    });
    WaitSet waitset(participant);
    for (const auto& echo : echoes) waitset.attach(echo->condition());
    std::printf("ready\n");
    std::fflush(stdout);
    const dds_time_t end = dds_time() + kLifetime;
    while (!stop_requested && dds_time() < end) {
      if (auto woke = waitset.wait(kStopPoll); !woke) {
        std::fprintf(stderr, "echo: %s\n", woke.error().c_str());
        return 1;
      }
      for (const auto& echo : echoes) echo->pump();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "echo: %s\n", e.what());
    return 1;
  }
  return 0;
}
