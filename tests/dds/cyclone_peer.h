// A ROS 2 peer on a second DDS vendor: Cyclone DDS's C API, with types compiled by its idlc from the same IDL as
// corridor's (drivers/dds/idl). It names types and topics as ROS 2's rmw layers do ("pkg::msg::dds_::Type_",
// "rt/topic"), so corridord must meet it exactly as it would meet RViz, Nav2 or a ROS 2 driver. For tests only.
#pragma once

#include <dds/dds.h>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace corridor::testing {

enum class PeerQos {
  kDefault,
  kLatched,
  kTf
};  // as drivers/dds/participant.h's (reliable; transient local; depth 100)

class CyclonePeer {
 public:
  // Joins `domain` on loopback only, discovering by unicast to 127.0.0.1 (loopback has no multicast here); with
  // `enclave` (a DDS Security enclave's directory, drivers/dds/device_options.h's kEnclaveFiles), by Cyclone's own
  // DDS Security plugins. One peer of a domain at a time in a process: Cyclone makes a domain once per process, and
  // with the security of its first participant.
  explicit CyclonePeer(int domain, const std::string& enclave = "");
  CyclonePeer(const CyclonePeer&) = delete;
  CyclonePeer& operator=(const CyclonePeer&) = delete;
  ~CyclonePeer();

  // A reader / writer of ROS 2 topic `name` ("/odom") with idlc's descriptor for its type.
  dds_entity_t Reader(const std::string& name, const dds_topic_descriptor_t& type, PeerQos qos = PeerQos::kDefault);
  dds_entity_t Writer(const std::string& name, const dds_topic_descriptor_t& type, PeerQos qos = PeerQos::kDefault);

  // Takes every sample waiting on `reader`, calling `f` with each (the sample is Cyclone's until `f` returns).
  template <typename T>
  int Take(dds_entity_t reader, const std::function<void(const T&)>& f) {
    int taken = 0;
    for (;;) {
      void* samples[1] = {nullptr};
      dds_sample_info_t info[1];
      const dds_return_t n = dds_take(reader, samples, info, 1, 1);
      if (n <= 0) break;
      if (info[0].valid_data) {
        f(*static_cast<const T*>(samples[0]));
        ++taken;
      }
      dds_return_loan(reader, samples, n);
    }
    return taken;
  }

  // Waits up to `timeout` for `done`, taking `reader`'s samples into `f` meanwhile.
  template <typename T>
  bool TakeUntil(dds_entity_t reader, const std::function<void(const T&)>& f, const std::function<bool()>& done,
                 std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      Take<T>(reader, f);
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  // How many of corridor's readers match `writer` now.
  int Matched(dds_entity_t writer) const;

 private:
  dds_entity_t TopicFor(const std::string& name, const dds_topic_descriptor_t& type);
  // dds_create_reader or dds_create_writer.
  using Endpoint = dds_entity_t (*)(dds_entity_t, dds_entity_t, const dds_qos_t*, const dds_listener_t*);
  dds_entity_t Create(Endpoint create, const std::string& name, const dds_topic_descriptor_t& type, PeerQos qos);

  dds_entity_t domain_ = 0;
  dds_entity_t participant_ = 0;
  // By ROS 2's type name (which each names): a renamed copy of idlc's descriptor, kept as long as the peer.
  std::map<std::string, std::unique_ptr<dds_topic_descriptor_t>> descriptors_;
  std::map<std::string, dds_entity_t> topics_;
};

// "geometry_msgs::msg::Twist" -> "geometry_msgs::msg::dds_::Twist_" (the rmw layers' mangling).
std::string RosTypeName(const std::string& idl_name);

}  // namespace corridor::testing
