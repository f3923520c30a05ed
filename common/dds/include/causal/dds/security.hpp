// DDS-Security (authentication, access control, encryption) for every participant, in one place.
// A PKI folder made by deploy/security/make-pki.sh holds the two CA certificates, the signed governance and
// one folder per identity (cert.pem, key.pem, permissions.p7s). A service names its identity from its
// participant name (sensor-replay -> sensor, ...), or is told one (--security-identity).
// Every file is checked BEFORE the participant is created, so a missing, unparsable, expired, revoked or
// foreign certificate, or a permissions document signed by someone else or for another subject, stops the
// service with a message naming the file and the problem (std::invalid_argument: exit code 2), instead of
// a participant that silently matches nobody.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include <cstdint>
#include <string>

namespace causal::dds {

// Participant property that switches security on from an XML profile (deploy/dds/plant.xml): its value is
// the PKI folder, or "off". --security DIR (or $CAUSAL_TWIN_SECURITY_DIR) takes precedence over it.
inline constexpr const char* kSecurityDirProperty = "causal_twin.security_dir";
inline constexpr const char* kSecurityOff = "off";

// The files of one identity in a PKI folder (make-pki.sh's layout). crl is "" when the CA revoked nothing.
struct SecurityFiles {
  std::string identity_ca;     // DIR/identity_ca.pem
  std::string permissions_ca;  // DIR/permissions_ca.pem
  std::string governance;      // DIR/governance.p7s
  std::string certificate;     // DIR/<identity>/cert.pem
  std::string private_key;     // DIR/<identity>/key.pem
  std::string permissions;     // DIR/<identity>/permissions.p7s
  std::string crl;             // DIR/identity_ca.crl if it exists
};

// The identity a service runs as, from its participant name: sensor-replay and sensor-sim -> "sensor",
// causal-estimator -> "estimator", alarm-recommender -> "recommender", causal-recorder -> "recorder",
// causal-ask -> "operator"; "" for any other name (it must then be given explicitly).
std::string default_security_identity(const std::string& participant_name);

SecurityFiles security_files(const std::string& dir, const std::string& identity);

// Checks every file as Fast DDS will use it, plus what Fast DDS only reports as a failed handshake later:
// each exists and parses; the certificates are within their validity dates; the identity certificate was
// issued by the identity CA and is not revoked; the key belongs to the certificate; governance and
// permissions are signed by the permissions CA; the permissions grant names this certificate's subject and
// is valid now. Throws std::invalid_argument "<file>: <problem>" on the first failure.
void check_security_files(const SecurityFiles& files);
// The same checks; returns the text of the grant for the certificate's subject (<grant ...> ... ), from the
// permissions document whose signature was verified.
std::string verified_grant(const SecurityFiles& files);

// Adds the builtin plugins' dds.sec.* properties (file:// URIs) to the participant QoS.
void add_security_properties(const SecurityFiles& files, eprosima::fastdds::dds::DomainParticipantQos& qos);

// Decides and applies the security of one participant: `dir` from the command line ("" = the profile's
// kSecurityDirProperty, if any; "off" = open). Returns a line for the log ("DDS-Security on: identity
// sensor from DIR" / "DDS-Security off"). A profile that already sets dds.sec.* properties itself keeps
// them (and they are checked too). Throws std::invalid_argument like check_security_files. `applied`, when
// given, receives what the participant needs later when security is on.
struct AppliedSecurity {
  std::string grant;                // the verified grant's text (group_partitions.hpp reads its partitions)
  std::int64_t certificate_expiry_s = 0;  // notAfter of the identity certificate, seconds since the epoch
  std::string crl;  // the revocation list it loads, or would load once it exists (revocation_watch.hpp)
};
std::string apply_security(const std::string& dir, const std::string& identity, const std::string& participant_name,
                           eprosima::fastdds::dds::DomainParticipantQos& qos, AppliedSecurity* applied = nullptr);

// notAfter of a PEM certificate, seconds since the epoch; throws std::invalid_argument naming the file.
std::int64_t certificate_expiry(const std::string& certificate);

}  // namespace causal::dds
