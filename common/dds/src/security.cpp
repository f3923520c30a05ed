#include "causal/dds/security.hpp"

#include "causal/io/time_format.hpp"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>

#include <ctime>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

namespace causal::dds {
namespace {

namespace fs = std::filesystem;
using X509Ptr = std::unique_ptr<X509, decltype(&X509_free)>;
using BioPtr = std::unique_ptr<BIO, decltype(&BIO_free_all)>;
using StorePtr = std::unique_ptr<X509_STORE, decltype(&X509_STORE_free)>;

[[noreturn]] void fail(const std::string& file, const std::string& problem) {
  throw std::invalid_argument("DDS-Security: " + file + ": " + problem);
}

std::string openssl_error() {
  std::string out;
  for (unsigned long e = ERR_get_error(); e != 0; e = ERR_get_error()) {
    char buf[256];
    ERR_error_string_n(e, buf, sizeof buf);
    if (out.empty()) out = buf;  // the first error is the root cause; drop the rest of the queue
  }
  return out.empty() ? std::string() : " (" + out + ")";
}

BioPtr open_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "missing");
  if (!fs::is_regular_file(path, ec)) fail(path, "not a regular file");
  BioPtr bio(BIO_new_file(path.c_str(), "r"), BIO_free_all);
  if (!bio) fail(path, "cannot be read" + openssl_error());
  return bio;
}

std::string bio_text(BIO* bio) {
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio, &data);
  return n > 0 ? std::string(data, static_cast<std::size_t>(n)) : std::string();
}

std::string time_text(const ASN1_TIME* t) {
  BioPtr bio(BIO_new(BIO_s_mem()), BIO_free_all);
  ASN1_TIME_print(bio.get(), t);
  return bio_text(bio.get());
}

std::string name_text(const X509_NAME* name) {
  BioPtr bio(BIO_new(BIO_s_mem()), BIO_free_all);
  X509_NAME_print_ex(bio.get(), name, 0, XN_FLAG_RFC2253);
  return bio_text(bio.get());
}

X509Ptr read_certificate(const std::string& path, const std::string& what) {
  BioPtr bio = open_file(path);
  X509Ptr cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr), X509_free);
  if (!cert) fail(path, "not a PEM " + what + openssl_error());
  if (X509_cmp_current_time(X509_get0_notBefore(cert.get())) >= 0) {
    fail(path, what + " not valid before " + time_text(X509_get0_notBefore(cert.get())));
  }
  if (X509_cmp_current_time(X509_get0_notAfter(cert.get())) <= 0) {
    fail(path, what + " expired on " + time_text(X509_get0_notAfter(cert.get())) + " (subject " +
                   name_text(X509_get_subject_name(cert.get())) + ")");
  }
  return cert;
}

StorePtr store_with(X509* ca) {
  StorePtr store(X509_STORE_new(), X509_STORE_free);
  if (!store || X509_STORE_add_cert(store.get(), ca) != 1) throw std::runtime_error("OpenSSL: cannot build a store");
  return store;
}

void check_issued_by(X509* cert, X509* ca, const SecurityFiles& f) {
  StorePtr store = store_with(ca);
  if (!f.crl.empty()) {
    BioPtr bio = open_file(f.crl);
    std::unique_ptr<X509_CRL, decltype(&X509_CRL_free)> crl(PEM_read_bio_X509_CRL(bio.get(), nullptr, nullptr, nullptr),
                                                           X509_CRL_free);
    if (!crl) fail(f.crl, "not a PEM certificate revocation list" + openssl_error());
    if (X509_CRL_verify(crl.get(), X509_get0_pubkey(ca)) != 1) fail(f.crl, "not signed by the identity CA " + f.identity_ca);
    X509_STORE_add_crl(store.get(), crl.get());
    X509_STORE_set_flags(store.get(), X509_V_FLAG_CRL_CHECK);
  }
  std::unique_ptr<X509_STORE_CTX, decltype(&X509_STORE_CTX_free)> ctx(X509_STORE_CTX_new(), X509_STORE_CTX_free);
  if (!ctx || X509_STORE_CTX_init(ctx.get(), store.get(), cert, nullptr) != 1) {
    throw std::runtime_error("OpenSSL: cannot set up a certificate check");
  }
  if (X509_verify_cert(ctx.get()) == 1) return;
  const int err = X509_STORE_CTX_get_error(ctx.get());
  if (err == X509_V_ERR_CERT_REVOKED) fail(f.certificate, "certificate revoked (listed in " + f.crl + ")");
  if (err == X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY || err == X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT ||
      err == X509_V_ERR_CERT_SIGNATURE_FAILURE || err == X509_V_ERR_DEPTH_ZERO_SELF_SIGNED_CERT) {
    fail(f.certificate, "not issued by the identity CA " + f.identity_ca + " (issuer " +
                            name_text(X509_get_issuer_name(cert)) + ", CA " + name_text(X509_get_subject_name(ca)) +
                            ")");
  }
  fail(f.certificate, std::string("rejected by the identity CA ") + f.identity_ca + ": " +
                          X509_verify_cert_error_string(err));
}

void check_private_key(const std::string& path, X509* cert, const std::string& cert_path) {
  BioPtr bio = open_file(path);
  // No pass-phrase prompt: a service must not block on a terminal.
  auto no_password = [](char*, int, int, void*) -> int { return 0; };
  std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> key(PEM_read_bio_PrivateKey(bio.get(), nullptr, no_password, nullptr),
                                                         EVP_PKEY_free);
  if (!key) fail(path, "not an unencrypted PEM private key" + openssl_error());
  if (X509_check_private_key(cert, key.get()) != 1) {
    ERR_clear_error();
    fail(path, "private key does not belong to the certificate " + cert_path);
  }
}

// The content of an S/MIME document signed by `ca`.
std::string signed_content(const std::string& path, X509* ca, const std::string& ca_path) {
  BioPtr bio = open_file(path);
  BIO* content = nullptr;
  std::unique_ptr<PKCS7, decltype(&PKCS7_free)> p7(SMIME_read_PKCS7(bio.get(), &content), PKCS7_free);
  BioPtr content_owner(content, BIO_free_all);
  if (!p7) fail(path, "not an S/MIME signed document" + openssl_error());
  StorePtr store = store_with(ca);
  BioPtr out(BIO_new(BIO_s_mem()), BIO_free_all);
  if (PKCS7_verify(p7.get(), nullptr, store.get(), content, out.get(), PKCS7_TEXT) != 1) {
    fail(path, "signature does not verify with the permissions CA " + ca_path + openssl_error());
  }
  return bio_text(out.get());
}

std::string between(const std::string& text, const std::string& open, const std::string& close, std::size_t& pos) {
  const std::size_t a = text.find(open, pos);
  if (a == std::string::npos) return {};
  const std::size_t b = text.find(close, a + open.size());
  if (b == std::string::npos) return {};
  pos = b + close.size();
  return text.substr(a + open.size(), b - a - open.size());
}

// "CN=a, OU=b" and "CN=a,OU=b" name the same subject (Fast DDS compares RFC 2253 names the same way).
std::string without_spaces_after_commas(std::string s) {
  std::string out;
  bool after_comma = false;
  for (char c : s) {
    if (after_comma && (c == ' ' || c == '\n' || c == '\t' || c == '\r')) continue;
    after_comma = (c == ',');
    out += c;
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == '\n')) out.pop_back();
  while (!out.empty() && (out.front() == ' ' || out.front() == '\n')) out.erase(out.begin());
  return out;
}

// "2026-11-23T16:20:27" (UTC) as seconds since the epoch; -1 when unreadable.
std::time_t utc_seconds(const std::string& text) {
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%dT%d:%d:%d", &year, &month, &day, &hour, &minute, &second) != 6) return -1;
  return static_cast<std::time_t>(io::utc_to_ns(year, month, day, hour, minute, second) / 1'000'000'000);
}

// Checks the grant for the certificate's subject and returns its text.
std::string check_permissions(const std::string& path, const std::string& xml, X509* cert, const std::string& cert_path) {
  const std::string subject = name_text(X509_get_subject_name(cert));
  const std::time_t now = std::time(nullptr);
  std::size_t pos = 0;
  bool any_grant = false;
  for (std::string grant = between(xml, "<grant", "</grant>", pos); !grant.empty();
       grant = between(xml, "<grant", "</grant>", pos)) {
    any_grant = true;
    std::size_t p = 0;
    if (without_spaces_after_commas(between(grant, "<subject_name>", "</subject_name>", p)) != subject) continue;
    p = 0;
    const std::string nb = between(grant, "<not_before>", "</not_before>", p);
    const std::string na = between(grant, "<not_after>", "</not_after>", p);
    const std::time_t from = utc_seconds(nb), to = utc_seconds(na);
    if (from < 0 || to < 0) fail(path, "grant for " + subject + " has unreadable validity dates");
    if (now < from) fail(path, "grant for " + subject + " not valid before " + nb + " UTC");
    if (now > to) fail(path, "grant for " + subject + " expired on " + na + " UTC");
    return grant;
  }
  if (!any_grant) fail(path, "no <grant> in the permissions document");
  fail(path, "no grant for the subject of " + cert_path + " (" + subject + ")");
}

// Fast DDS reads "file://PATH" (absolute: file:///tmp/...).
std::string strip_file_uri(const std::string& uri) { return uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri; }

const std::string* find_property(const eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& name) {
  for (const auto& p : qos.properties().properties()) {
    if (p.name() == name) return &p.value();
  }
  return nullptr;
}

}  // namespace

std::string default_security_identity(const std::string& participant_name) {
  if (participant_name == "sensor-replay" || participant_name == "sensor-sim") return "sensor";
  // The edge adapter has its own identity (sensor grants): revoking it does not stop replays or simulators,
  // and one taken from an edge host cannot pass for them.
  if (participant_name == "sensor-ingest") return "ingest";
  if (participant_name == "causal-estimator") return "estimator";
  if (participant_name == "alarm-recommender") return "recommender";
  if (participant_name == "causal-recorder") return "recorder";
  if (participant_name == "causal-ask" || participant_name == "twin-web" || participant_name == "causal-alarm-action" ||
      participant_name == "causal-approve") {
    return "operator";  // read + what-if + alarm actions + approvals
  }
  return {};
}

SecurityFiles security_files(const std::string& dir, const std::string& identity) {
  const fs::path d = fs::absolute(dir);
  SecurityFiles f;
  f.identity_ca = (d / "identity_ca.pem").string();
  f.permissions_ca = (d / "permissions_ca.pem").string();
  f.governance = (d / "governance.p7s").string();
  f.certificate = (d / identity / "cert.pem").string();
  f.private_key = (d / identity / "key.pem").string();
  f.permissions = (d / identity / "permissions.p7s").string();
  std::error_code ec;
  if (fs::exists(d / "identity_ca.crl", ec)) f.crl = (d / "identity_ca.crl").string();
  return f;
}

void check_security_files(const SecurityFiles& f) { (void)verified_grant(f); }

std::int64_t certificate_expiry(const std::string& certificate) {
  BioPtr bio = open_file(certificate);
  X509Ptr cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr), X509_free);
  if (!cert) fail(certificate, "not a PEM certificate" + openssl_error());
  std::tm tm{};
  if (ASN1_TIME_to_tm(X509_get0_notAfter(cert.get()), &tm) != 1) fail(certificate, "unreadable expiry date");
  return io::utc_to_ns(tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec) / 1'000'000'000;
}

std::string verified_grant(const SecurityFiles& f) {
  ERR_clear_error();
  X509Ptr identity_ca = read_certificate(f.identity_ca, "identity CA certificate");
  X509Ptr permissions_ca = read_certificate(f.permissions_ca, "permissions CA certificate");
  X509Ptr cert = read_certificate(f.certificate, "identity certificate");
  check_issued_by(cert.get(), identity_ca.get(), f);
  check_private_key(f.private_key, cert.get(), f.certificate);
  const std::string governance = signed_content(f.governance, permissions_ca.get(), f.permissions_ca);
  if (governance.find("<domain_access_rules>") == std::string::npos) {
    fail(f.governance, "not a governance document (no <domain_access_rules>)");
  }
  const std::string permissions = signed_content(f.permissions, permissions_ca.get(), f.permissions_ca);
  return check_permissions(f.permissions, permissions, cert.get(), f.certificate);
}

void add_security_properties(const SecurityFiles& f, eprosima::fastdds::dds::DomainParticipantQos& qos) {
  auto& p = qos.properties().properties();
  const std::string auth = "dds.sec.auth.builtin.PKI-DH.";
  const std::string access = "dds.sec.access.builtin.Access-Permissions.";
  p.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  p.emplace_back(auth + "identity_ca", "file://" + f.identity_ca);
  p.emplace_back(auth + "identity_certificate", "file://" + f.certificate);
  p.emplace_back(auth + "private_key", "file://" + f.private_key);
  if (!f.crl.empty()) p.emplace_back(auth + "identity_crl", "file://" + f.crl);
  p.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  p.emplace_back(access + "permissions_ca", "file://" + f.permissions_ca);
  p.emplace_back(access + "governance", "file://" + f.governance);
  p.emplace_back(access + "permissions", "file://" + f.permissions);
  p.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

std::string apply_security(const std::string& dir, const std::string& identity, const std::string& participant_name,
                           eprosima::fastdds::dds::DomainParticipantQos& qos, AppliedSecurity* applied) {
  std::string chosen = dir;
  std::string source = "--security";
  auto& props = qos.properties().properties();
  for (auto it = props.begin(); it != props.end(); ++it) {
    if (it->name() != kSecurityDirProperty) continue;
    if (chosen.empty()) {
      chosen = it->value();
      source = "the DDS profile's " + std::string(kSecurityDirProperty);
    }
    props.erase(it);  // ours, not Fast DDS's
    break;
  }
  if (!chosen.empty() && chosen != kSecurityOff) {
    if (find_property(qos, "dds.sec.auth.plugin") != nullptr) {
      throw std::invalid_argument("DDS-Security: the DDS profile sets dds.sec.* properties itself and " + source +
                                  " names " + chosen + ": use one or the other");
    }
    const std::string id = identity.empty() ? default_security_identity(participant_name) : identity;
    if (id.empty()) {
      throw std::invalid_argument("DDS-Security: participant '" + participant_name +
                                  "' has no default identity: pass --security-identity NAME");
    }
    std::error_code ec;
    if (!fs::is_directory(chosen, ec)) {
      throw std::invalid_argument("DDS-Security: PKI folder " + chosen + " (from " + source +
                                  ") does not exist: make one with deploy/security/make-pki.sh DIR");
    }
    SecurityFiles files = security_files(chosen, id);
    // Under systemd, LoadCredential=dds-key.pem:/path/to/IDENTITY/key.pem hands this unit, and only it, its
    // private key (the file itself can stay root-only): it then replaces the PKI folder's key.pem.
    std::string key_note;
    if (const char* creds = std::getenv("CREDENTIALS_DIRECTORY"); creds != nullptr && *creds != '\0') {
      const fs::path key = fs::path(creds) / "dds-key.pem";
      if (fs::exists(key, ec)) {
        files.private_key = key.string();
        key_note = ", key from the systemd credential dds-key.pem";
      }
    }
    const std::string checked = verified_grant(files);
    if (applied != nullptr) {
      *applied = {checked, certificate_expiry(files.certificate), (fs::absolute(chosen) / "identity_ca.crl").string()};
    }
    add_security_properties(files, qos);
    return "DDS-Security on: identity " + id + " from " + fs::absolute(chosen).string() + " (" + source + key_note +
           ")";
  }
  if (const std::string* plugin = find_property(qos, "dds.sec.auth.plugin"); plugin != nullptr) {
    // The profile configures the plugins itself: check the files it names all the same.
    auto file_of = [&](const std::string& name) {
      const std::string* v = find_property(qos, name);
      if (v == nullptr) throw std::invalid_argument("DDS-Security: the DDS profile does not set " + name);
      return strip_file_uri(*v);
    };
    const std::string auth = "dds.sec.auth.builtin.PKI-DH.";
    const std::string access = "dds.sec.access.builtin.Access-Permissions.";
    SecurityFiles f;
    f.identity_ca = file_of(auth + "identity_ca");
    f.certificate = file_of(auth + "identity_certificate");
    f.private_key = file_of(auth + "private_key");
    if (const std::string* crl = find_property(qos, auth + "identity_crl")) f.crl = strip_file_uri(*crl);
    f.permissions_ca = file_of(access + "permissions_ca");
    f.governance = file_of(access + "governance");
    f.permissions = file_of(access + "permissions");
    const std::string checked = verified_grant(f);
    if (applied != nullptr) *applied = {checked, certificate_expiry(f.certificate), f.crl};
    return "DDS-Security on: configured by the DDS profile (" + f.certificate + ")";
  }
  return "DDS-Security off (open bus: any process on this domain can read and publish; see README, Security)";
}

}  // namespace causal::dds
