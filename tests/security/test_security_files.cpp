// The credential checks made before a secured participant is created (common/dds security.hpp), on PKIs made
// by the shipped scripts: every broken set-up must be refused with a message naming the file and the problem,
// and every identity make-pki.sh issues must pass.
#include "causal/dds/security.hpp"
#include "pki_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <iterator>

using namespace causal::test::security;
using causal::dds::check_security_files;
using causal::dds::security_files;

namespace {

// Made on first use (ctest runs every test in its own process; openssl takes about a second per PKI).
const fs::path& root() {
  static const fs::path r = fresh_dir("files");
  return r;
}
const fs::path& pki() {
  static const fs::path p = make_pki(root() / "pki");
  return p;
}
const fs::path& other_pki() {  // another identity CA and permissions CA
  static const fs::path p = make_pki(root() / "other");
  return p;
}

class SecurityFiles : public ::testing::Test {
 protected:
  static void TearDownTestSuite() { fs::remove_all(root()); }

  // The message of the std::invalid_argument thrown for `identity` in `pki` ("" when none is thrown).
  static std::string refusal(const fs::path& pki, const std::string& identity) {
    try {
      check_security_files(security_files(pki.string(), identity));
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return {};
  }
};

void expect_refused(const std::string& message, const std::string& file, const std::string& problem) {
  EXPECT_NE(message.find(file), std::string::npos) << "names no " << file << ": " << message;
  EXPECT_NE(message.find(problem), std::string::npos) << "does not say '" << problem << "': " << message;
}

}  // namespace

TEST_F(SecurityFiles, EveryIssuedIdentityPasses) {
  for (const char* id : {"sensor", "estimator", "recommender", "recorder", "operator"}) {
    EXPECT_EQ(refusal(pki(), id), "") << id;
  }
}

TEST_F(SecurityFiles, MissingCertificateIsNamed) {
  expect_refused(refusal(pki(), "nobody"), (pki() / "nobody" / "cert.pem").string(), "missing");
}

TEST_F(SecurityFiles, ExpiredCertificateIsNamedWithItsDate) {
  run(script("issue-identity.sh") + " '" + pki().string() + "' old sensor --expired");
  expect_refused(refusal(pki(), "old"), (pki() / "old" / "cert.pem").string(), "expired on Jan  2 00:00:00 2020");
}

TEST_F(SecurityFiles, CertificateFromAnotherCaIsRefused) {
  assemble_identity(pki(), "foreign", other_pki() / "sensor", other_pki() / "sensor", pki() / "sensor");
  expect_refused(refusal(pki(), "foreign"), (pki() / "foreign" / "cert.pem").string(),
                 "not issued by the identity CA " + (pki() / "identity_ca.pem").string());
}

TEST_F(SecurityFiles, KeyOfAnotherIdentityIsRefused) {
  assemble_identity(pki(), "wrong_key", pki() / "sensor", pki() / "estimator", pki() / "sensor");
  expect_refused(refusal(pki(), "wrong_key"), (pki() / "wrong_key" / "key.pem").string(), "does not belong");
}

TEST_F(SecurityFiles, PermissionsOfAnotherSubjectAreRefused) {
  // The estimator's certificate with the sensor's permissions: the grant names CN=sensor.
  assemble_identity(pki(), "borrowed", pki() / "estimator", pki() / "estimator", pki() / "sensor");
  expect_refused(refusal(pki(), "borrowed"), (pki() / "borrowed" / "permissions.p7s").string(),
                 "no grant for the subject of");
}

TEST_F(SecurityFiles, PermissionsSignedByAnotherCaAreRefused) {
  // Same subject (CN=sensor,...), but the document is signed by the other PKI's permissions CA.
  assemble_identity(pki(), "forged", pki() / "sensor", pki() / "sensor", other_pki() / "sensor");
  expect_refused(refusal(pki(), "forged"), (pki() / "forged" / "permissions.p7s").string(),
                 "signature does not verify with the permissions CA");
}

TEST_F(SecurityFiles, EditedGovernanceIsRefused) {
  const fs::path copy = fresh_dir("edited_governance");
  fs::copy(pki(), copy / "pki", fs::copy_options::recursive);
  const fs::path file = copy / "pki" / "governance.p7s";
  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const auto at = text.find("<allow_unauthenticated_participants>false");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 41, "<allow_unauthenticated_participants>true ");
  std::ofstream(file) << text;
  expect_refused(refusal(copy / "pki", "sensor"), file.string(), "signature does not verify");
  fs::remove_all(copy);
}

TEST_F(SecurityFiles, RevokedCertificateIsRefused) {
  // A PKI of its own: the revocation list would apply to every identity of pki().
  const fs::path copy = fresh_dir("revoked");
  const fs::path pki = make_pki(copy / "pki");
  run(script("issue-identity.sh") + " '" + pki.string() + "' retired sensor");
  EXPECT_EQ(refusal(pki, "retired"), "");
  run(script("revoke-identity.sh") + " '" + pki.string() + "' retired");
  expect_refused(refusal(pki, "retired"), (pki / "retired" / "cert.pem").string(), "certificate revoked");
  EXPECT_EQ(refusal(pki, "sensor"), "") << "revoking one identity must not refuse the others";
  fs::remove_all(copy);
}

TEST_F(SecurityFiles, ApplySecurityAddsThePluginsAndTakesTheProfileFolder) {
  eprosima::fastdds::dds::DomainParticipantQos qos;
  qos.properties().properties().emplace_back(causal::dds::kSecurityDirProperty, pki().string());
  const std::string line = causal::dds::apply_security("", "", "causal-estimator", qos);
  EXPECT_NE(line.find("DDS-Security on: identity estimator"), std::string::npos) << line;
  std::map<std::string, std::string> props;
  for (const auto& p : qos.properties().properties()) props[p.name()] = p.value();
  EXPECT_EQ(props.count(causal::dds::kSecurityDirProperty), 0u) << "the folder property is ours, not Fast DDS's";
  EXPECT_EQ(props["dds.sec.auth.plugin"], "builtin.PKI-DH");
  EXPECT_EQ(props["dds.sec.access.plugin"], "builtin.Access-Permissions");
  EXPECT_EQ(props["dds.sec.crypto.plugin"], "builtin.AES-GCM-GMAC");
  EXPECT_EQ(props["dds.sec.auth.builtin.PKI-DH.identity_certificate"], "file://" + (pki() / "estimator" / "cert.pem").string());
  EXPECT_EQ(props["dds.sec.access.builtin.Access-Permissions.permissions"],
            "file://" + (pki() / "estimator" / "permissions.p7s").string());
}

TEST_F(SecurityFiles, CommandLineOffOverridesTheProfileAndUnknownServicesNeedAnIdentity) {
  eprosima::fastdds::dds::DomainParticipantQos qos;
  qos.properties().properties().emplace_back(causal::dds::kSecurityDirProperty, pki().string());
  EXPECT_EQ(causal::dds::apply_security("off", "", "causal-estimator", qos).rfind("DDS-Security off", 0), 0u);
  for (const auto& p : qos.properties().properties()) {
    EXPECT_NE(p.name(), causal::dds::kSecurityDirProperty);
    EXPECT_NE(p.name().rfind("dds.sec.", 0), 0u) << p.name();
  }

  eprosima::fastdds::dds::DomainParticipantQos other;
  EXPECT_THROW(causal::dds::apply_security(pki().string(), "", "some-tool", other), std::invalid_argument);
  try {
    causal::dds::apply_security("/nonexistent/pki", "", "causal-recorder", other);
    ADD_FAILURE() << "a missing PKI folder must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/pki"), std::string::npos) << e.what();
  }
}

TEST_F(SecurityFiles, ProfileWithItsOwnSecurityPropertiesIsCheckedToo) {
  // A site that writes the dds.sec.* properties into its XML profile by hand gets the same checks.
  eprosima::fastdds::dds::DomainParticipantQos qos;
  causal::dds::add_security_properties(security_files(pki().string(), "recorder"), qos);
  EXPECT_NE(causal::dds::apply_security("", "", "causal-recorder", qos).find("configured by the DDS profile"),
            std::string::npos);
  eprosima::fastdds::dds::DomainParticipantQos broken;
  auto files = security_files(pki().string(), "recorder");
  files.private_key = (pki() / "sensor" / "key.pem").string();
  causal::dds::add_security_properties(files, broken);
  try {
    causal::dds::apply_security("", "", "causal-recorder", broken);
    ADD_FAILURE() << "the sensor's key with the recorder's certificate must be refused";
  } catch (const std::invalid_argument& e) {
    expect_refused(e.what(), files.private_key, "does not belong");
  }
}
