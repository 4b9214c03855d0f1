#include "tests/dds/cyclone_peer.h"

#include <stdexcept>
#include <utility>

namespace corridor::testing {
namespace {

std::string TopicName(const std::string& name) { return "rt/" + (name.front() == '/' ? name.substr(1) : name); }

dds_qos_t* QosFor(PeerQos qos) {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q, qos == PeerQos::kLatched ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, qos == PeerQos::kLatched ? 1 : qos == PeerQos::kTf ? 100 : 10);
  // Classic CDR (XCDR1), as ROS 2's rmw layers write it: Fast DDS 2.9 reads no other encoding.
  const dds_data_representation_id_t xcdr1[] = {DDS_DATA_REPRESENTATION_XCDR1};
  dds_qset_data_representation(q, 1, xcdr1);
  return q;
}

void Check(dds_entity_t e, const std::string& what) {
  if (e < 0) throw std::runtime_error("cyclone: " + what + ": " + dds_strretcode(e));
}

}  // namespace

std::string RosTypeName(const std::string& idl_name) {
  const std::size_t last = idl_name.rfind("::");
  if (last == std::string::npos) throw std::invalid_argument("not a scoped type name: " + idl_name);
  return idl_name.substr(0, last) + "::dds_::" + idl_name.substr(last + 2) + "_";
}

CyclonePeer::CyclonePeer(int domain, const std::string& enclave) {
  const std::string config =
      "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
      "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
      "<MaxAutoParticipantIndex>20</MaxAutoParticipantIndex><Peers><Peer address=\"127.0.0.1\"/></Peers>"
      "</Discovery></Domain></CycloneDDS>";
  domain_ = dds_create_domain(static_cast<dds_domainid_t>(domain), config.c_str());
  Check(domain_, "create domain");
  dds_qos_t* qos = dds_create_qos();
  if (!enclave.empty()) {
    auto uri = [&](const char* file) { return "file:" + enclave + "/" + file; };
    const std::pair<const char*, std::string> properties[] = {
        {"dds.sec.auth.library.path", "dds_security_auth"},
        {"dds.sec.auth.library.init", "init_authentication"},
        {"dds.sec.auth.library.finalize", "finalize_authentication"},
        {"dds.sec.crypto.library.path", "dds_security_crypto"},
        {"dds.sec.crypto.library.init", "init_crypto"},
        {"dds.sec.crypto.library.finalize", "finalize_crypto"},
        {"dds.sec.access.library.path", "dds_security_ac"},
        {"dds.sec.access.library.init", "init_access_control"},
        {"dds.sec.access.library.finalize", "finalize_access_control"},
        {"dds.sec.auth.identity_ca", uri("identity_ca.cert.pem")},
        {"dds.sec.auth.identity_certificate", uri("cert.pem")},
        {"dds.sec.auth.private_key", uri("key.pem")},
        {"dds.sec.access.permissions_ca", uri("permissions_ca.cert.pem")},
        {"dds.sec.access.governance", uri("governance.p7s")},
        {"dds.sec.access.permissions", uri("permissions.p7s")},
    };
    for (const auto& [name, value] : properties) dds_qset_prop(qos, name, value.c_str());
  }
  participant_ = dds_create_participant(static_cast<dds_domainid_t>(domain), qos, nullptr);
  dds_delete_qos(qos);
  Check(participant_, "create participant");
}

CyclonePeer::~CyclonePeer() { dds_delete(domain_); }

dds_entity_t CyclonePeer::TopicFor(const std::string& name, const dds_topic_descriptor_t& type) {
  const std::string topic = TopicName(name);
  if (const auto it = topics_.find(topic); it != topics_.end()) return it->second;
  const std::string ros_name = RosTypeName(type.m_typename);
  const auto [it, added] = descriptors_.try_emplace(ros_name);
  auto& descriptor = it->second;
  if (added) {
    // The same layout and marshalling program as idlc made, under ROS 2's name, without XTypes information (which
    // would carry idlc's name; Fast DDS here sends none, so types match by name, as between ROS 2 vendors).
    descriptor.reset(new dds_topic_descriptor_t{type.m_size,
                                                type.m_align,
                                                type.m_flagset & ~DDS_TOPIC_XTYPES_METADATA,
                                                type.m_nkeys,
                                                it->first.c_str(),  // the map's key: stable
                                                type.m_keys,
                                                type.m_nops,
                                                type.m_ops,
                                                type.m_meta,
                                                {nullptr, 0},
                                                {nullptr, 0},
                                                type.restrict_data_representation});
  }
  const dds_entity_t t = dds_create_topic(participant_, descriptor.get(), topic.c_str(), nullptr, nullptr);
  Check(t, "create topic " + topic);
  topics_[topic] = t;
  return t;
}

dds_entity_t CyclonePeer::Create(Endpoint create, const std::string& name, const dds_topic_descriptor_t& type,
                                 PeerQos qos) {
  dds_qos_t* q = QosFor(qos);
  const dds_entity_t e = create(participant_, TopicFor(name, type), q, nullptr);
  dds_delete_qos(q);
  Check(e, "create a reader or writer of " + name);
  return e;
}

dds_entity_t CyclonePeer::Reader(const std::string& name, const dds_topic_descriptor_t& type, PeerQos qos) {
  return Create(dds_create_reader, name, type, qos);
}

dds_entity_t CyclonePeer::Writer(const std::string& name, const dds_topic_descriptor_t& type, PeerQos qos) {
  return Create(dds_create_writer, name, type, qos);
}

int CyclonePeer::Matched(dds_entity_t writer) const {
  dds_publication_matched_status_t status{};
  if (dds_get_publication_matched_status(writer, &status) != DDS_RETCODE_OK) return 0;
  return static_cast<int>(status.current_count);
}

}  // namespace corridor::testing
