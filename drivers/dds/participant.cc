#include "drivers/dds/participant.h"

#include "drivers/dds/device_options.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <spdlog/spdlog.h>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <sstream>

namespace corridor::drivers::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;

constexpr auto kDropLogPeriod = std::chrono::seconds(5);
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;

template <typename EntityQos>
void ApplyProfile(EntityQos& q, Qos qos) {
  const bool reliable = qos != Qos::kSensor;
  q.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
  q.durability().kind = qos == Qos::kLatched ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  q.history().depth = qos == Qos::kLatched ? 1 : qos == Qos::kSensor ? 5 : qos == Qos::kTf ? 100 : 10;
  // Samples go over the network transport only (no shared memory): what other vendors' peers see is what ours see.
  q.data_sharing().off();
}

// DDS Security's builtin plugins (authentication by PKI-DH, access control by signed permissions, AES-GCM-GMAC
// cryptography) with the enclave's files.
void ApplySecurity(fdds::DomainParticipantQos& qos, const std::string& enclave) {
  if (const std::string file = UnreadableEnclaveFile(enclave); !file.empty()) {
    throw std::invalid_argument("dds: the security enclave has no readable " + file);
  }
  auto uri = [&](const char* file) { return "file://" + enclave + "/" + file; };
  const std::pair<const char*, std::string> properties[] = {
      {"dds.sec.auth.plugin", "builtin.PKI-DH"},
      {"dds.sec.auth.builtin.PKI-DH.identity_ca", uri("identity_ca.cert.pem")},
      {"dds.sec.auth.builtin.PKI-DH.identity_certificate", uri("cert.pem")},
      {"dds.sec.auth.builtin.PKI-DH.private_key", uri("key.pem")},
      {"dds.sec.access.plugin", "builtin.Access-Permissions"},
      {"dds.sec.access.builtin.Access-Permissions.permissions_ca", uri("permissions_ca.cert.pem")},
      {"dds.sec.access.builtin.Access-Permissions.governance", uri("governance.p7s")},
      {"dds.sec.access.builtin.Access-Permissions.permissions", uri("permissions.p7s")},
      {"dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC"},
  };
  for (const auto& [name, value] : properties) qos.properties().properties().emplace_back(name, value);
}

}  // namespace

std::string RosTopic(const std::string& name) {
  if (!IsRosTopicName(name)) throw std::invalid_argument("'" + name + "' is not a ROS 2 topic name");
  return "rt/" + (name.front() == '/' ? name.substr(1) : name);
}

std::vector<std::string> InterfaceAddresses(const std::vector<std::string>& interfaces) {
  std::vector<std::string> out;
  ifaddrs* all = nullptr;
  if (::getifaddrs(&all) != 0) throw std::runtime_error("cannot list the network interfaces");
  const std::unique_ptr<ifaddrs, void (*)(ifaddrs*)> guard(all, ::freeifaddrs);
  for (const std::string& wanted : interfaces) {
    if (IsIpv4Address(wanted)) {
      out.push_back(wanted);
      continue;
    }
    bool found = false;
    for (const ifaddrs* i = all; i != nullptr; i = i->ifa_next) {
      if (i->ifa_addr == nullptr || i->ifa_addr->sa_family != AF_INET || wanted != i->ifa_name) continue;
      char text[INET_ADDRSTRLEN] = {};
      ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(i->ifa_addr)->sin_addr, text, sizeof(text));
      out.emplace_back(text);
      found = true;
    }
    if (!found) throw std::invalid_argument("no network interface '" + wanted + "' with an IPv4 address");
  }
  return out;
}

// Logs who comes and goes; discovery only (see the constructor).
class Participant::ParticipantListener final : public fdds::DomainParticipantListener {
 public:
  void on_participant_discovery(fdds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    using Status = eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERY_STATUS;
    if (info.status == Status::DISCOVERED_PARTICIPANT) {
      spdlog::info("dds: discovered participant '{}'", info.info.m_participantName.to_string());
    } else if (info.status == Status::REMOVED_PARTICIPANT || info.status == Status::DROPPED_PARTICIPANT) {
      spdlog::info("dds: participant '{}' left", info.info.m_participantName.to_string());
    }
  }
  void onParticipantAuthentication(fdds::DomainParticipant*,
                                   eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) override {
    using Status = eprosima::fastrtps::rtps::ParticipantAuthenticationInfo::AUTHENTICATION_STATUS;
    std::ostringstream guid;
    guid << info.guid;
    if (info.status == Status::UNAUTHORIZED_PARTICIPANT) {
      spdlog::warn("dds: participant {} failed authentication: not let in", guid.str());
    } else {
      spdlog::info("dds: participant {} authenticated", guid.str());
    }
  }
};

namespace {

// Takes a reader's samples while its subscription's gate is open; what throws is logged and dropped.
class ReaderListener final : public fdds::DataReaderListener {
 public:
  ReaderListener(std::string topic, std::shared_ptr<Subscription::Gate> gate,
                 std::function<void(fdds::DataReader&)> take)
      : topic_(std::move(topic)), gate_(std::move(gate)), take_(std::move(take)) {}
  void on_requested_incompatible_qos(fdds::DataReader*, const fdds::RequestedIncompatibleQosStatus&) override {
    spdlog::warn("dds: a writer of {} offers QoS this reader cannot take (reliability or durability)", topic_);
  }
  void on_data_available(fdds::DataReader* reader) override {
    std::lock_guard lock(gate_->mutex);
    if (!gate_->open) return;
    try {
      take_(*reader);
    } catch (const std::exception& e) {
      spdlog::warn("dds: a sample on {} was dropped: {}", topic_, e.what());
    }
  }

 private:
  std::string topic_;
  std::shared_ptr<Subscription::Gate> gate_;
  std::function<void(fdds::DataReader&)> take_;
};

}  // namespace

Participant::Participant(const ParticipantOptions& options)
    : options_(options), participant_listener_(std::make_unique<ParticipantListener>()) {
  if (options.domain_id < 0 || options.domain_id > 232) {
    throw std::runtime_error("dds: domain id " + std::to_string(options.domain_id) + " is not within 0..232");
  }
  fdds::DomainParticipantQos qos;
  qos.name(options.name);
  // UDP only, on the chosen interfaces.
  qos.transport().use_builtin_transports = false;
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  for (const std::string& address : InterfaceAddresses(options.interfaces)) udp->interfaceWhiteList.push_back(address);
  qos.transport().user_transports.push_back(udp);
  auto& builtin = qos.wire_protocol().builtin;
  if (!options.peers.empty()) {
    // Unicast discovery: listen on the well-known unicast ports (a zero port) of the allowed addresses (a null
    // address), announce to the peers only; no multicast locator at all.
    for (const std::string& peer : options.peers) {
      if (!IsIpv4Address(peer)) throw std::invalid_argument("dds: peer '" + peer + "' is not an IPv4 address");
      Locator_t locator;
      locator.kind = LOCATOR_KIND_UDPv4;
      IPLocator::setIPv4(locator, peer);
      builtin.initialPeersList.push_back(locator);
    }
    Locator_t any;
    any.kind = LOCATOR_KIND_UDPv4;
    builtin.metatrafficUnicastLocatorList.push_back(any);
    qos.wire_protocol().default_unicast_locator_list.push_back(any);
    builtin.metatrafficMulticastLocatorList.clear();
  }
  if (!options.security_enclave.empty()) ApplySecurity(qos, options.security_enclave);
  participant_ = fdds::DomainParticipantFactory::get_instance()->create_participant(
      static_cast<fdds::DomainId_t>(options.domain_id), qos, participant_listener_.get(),
      // Discovery only: with data_on_readers in its mask the participant's listener would take every reader's data
      // before the readers' own listeners see it.
      fdds::StatusMask::none());
  if (participant_ == nullptr) {
    throw std::runtime_error(options.security_enclave.empty()
                                 ? "dds: cannot create the participant (see the log above)"
                                 : "dds: cannot create the participant with the security enclave " +
                                       options.security_enclave + " (see the log above: a certificate, key or " +
                                       "signed document that does not verify)");
  }
  publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (publisher_ == nullptr || subscriber_ == nullptr) {
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
    throw std::runtime_error("dds: cannot create the publisher or subscriber");
  }
}

Participant::~Participant() {
  participant_->set_listener(nullptr);
  participant_->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

fdds::Topic* Participant::TopicFor(const std::string& name, fdds::TopicDataType* type) {
  fdds::TypeSupport support(type);  // owns `type` from here
  const std::string topic = RosTopic(name);
  std::lock_guard lock(mutex_);
  if (const auto it = topics_.find(topic); it != topics_.end()) {
    if (it->second->get_type_name() != support.get_type_name()) {
      throw std::invalid_argument("dds: " + name + " is already used with type " + it->second->get_type_name());
    }
    return it->second;
  }
  if (participant_->find_type(support.get_type_name()).empty() &&
      support.register_type(participant_) != ReturnCode::RETCODE_OK) {
    throw std::runtime_error("dds: cannot register type " + support.get_type_name());
  }
  fdds::Topic* t = participant_->create_topic(topic, support.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (t == nullptr) throw std::runtime_error("dds: cannot create topic " + topic);
  topics_.emplace(topic, t);
  return t;
}

fdds::DataWriter* Participant::CreateWriter(const std::string& name, fdds::TopicDataType* type, Qos qos, bool large) {
  fdds::Topic* topic = TopicFor(name, type);
  fdds::DataWriterQos q = fdds::DATAWRITER_QOS_DEFAULT;
  ApplyProfile(q, qos);
  q.publish_mode().kind = large ? fdds::ASYNCHRONOUS_PUBLISH_MODE : fdds::SYNCHRONOUS_PUBLISH_MODE;
  fdds::DataWriter* writer = publisher_->create_datawriter(topic, q, nullptr);
  if (writer == nullptr) throw std::runtime_error("dds: cannot create a writer of " + name);
  return writer;
}

std::unique_ptr<Subscription> Participant::CreateReader(const std::string& name, fdds::TopicDataType* type, Qos qos,
                                                        std::function<void(fdds::DataReader&)> take) {
  fdds::Topic* topic = TopicFor(name, type);
  fdds::DataReaderQos q = fdds::DATAREADER_QOS_DEFAULT;
  ApplyProfile(q, qos);
  auto gate = std::make_shared<Subscription::Gate>();
  auto listener = std::make_unique<ReaderListener>(name, gate, std::move(take));
  fdds::DataReader* reader = subscriber_->create_datareader(topic, q, listener.get());
  if (reader == nullptr) throw std::runtime_error("dds: cannot create a reader of " + name);
  return std::unique_ptr<Subscription>(new Subscription(subscriber_, reader, std::move(listener), std::move(gate)));
}

Subscription::~Subscription() {
  {
    std::lock_guard lock(gate_->mutex);  // waits for a delivery in progress
    gate_->open = false;
  }
  reader_->set_listener(nullptr);
  subscriber_->delete_datareader(reader_);
}

void DropLog::Drop(const std::string& why) {
  const std::uint64_t dropped = ++dropped_;
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  if (last_log_ != std::chrono::steady_clock::time_point{} && now - last_log_ < kDropLogPeriod) return;
  last_log_ = now;
  spdlog::warn("dds {}: a sample was dropped ({} so far): {}", what_, dropped, why);
}

}  // namespace corridor::drivers::dds
