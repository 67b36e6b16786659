// RAII DDS participant built from the XML QoS profiles in deploy/qos/.
#include "participant.hpp"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdlib>
#include <ctime>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include "deploy_dir.hpp"
#include "yaml_config.hpp"

namespace windfdi {
void register_type_objects();  // idl/register_type_objects.cpp
}

namespace windfdi::bus {

using namespace eprosima::fastdds::dds;

std::string resolve_qos_file(const std::string& requested) {
  if (!requested.empty()) return requested;
  if (const char* env = std::getenv("WINDFDI_QOS_FILE"); env && *env) return env;
  return deploy_dir() + "/qos/windfdi_qos.xml";
}

namespace {
// The factory is process-wide; each profile file is loaded into it once.
void load_profiles_once(const std::string& file) {
  static std::mutex mutex;
  static std::set<std::string> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  if (loaded.count(file)) return;
  if (!std::filesystem::exists(file)) throw ConfigError(file, 0, "", "QoS profile file not found");
  if (DomainParticipantFactory::get_instance()->load_XML_profiles_file(file) != ReturnCode_t::RETCODE_OK)
    throw ConfigError(file, 0, "", "Fast DDS rejected the QoS profile file (see its log above)");
  loaded.insert(file);
  for (const char* var :
       {"FASTRTPS_DEFAULT_PROFILES_FILE", "FASTDDS_ENVIRONMENT_FILE", "ROS_DISCOVERY_SERVER"})
    if (const char* v = std::getenv(var); v && *v)
      spdlog::warn("{}={} is set: it changes Fast DDS behaviour beside {}", var, v, file);
}
}  // namespace

// ---------------------------------------------------------------------------------------------------------
// DDS-Security: credentials by role, checked before the participant exists.

std::string security_role_for(const std::string& participant_name) {
  const std::string prefix = "windfdi-";
  if (participant_name.rfind(prefix, 0) != 0) return "";
  std::string rest = participant_name.substr(prefix.size());
  for (auto& c : rest)
    if (c == '-') c = '_';
  if (rest == "farm" || rest == "farm_ack") return "farm";
  static const std::set<std::string> roles = {"plant",       "arbiter",    "blade_load",
                                              "sensor_bias", "pitch_diag", "ice_detect"};
  return roles.count(rest) ? rest : "";
}

SecurityFiles security_files(const std::string& dir, const std::string& role) {
  if (role.empty() || role.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-") != std::string::npos)
    throw ConfigError("--security-role", 0, "",
                      "'" + role + "' is not a role name (letters, digits, _ and -)");
  const std::filesystem::path d = std::filesystem::absolute(dir);
  SecurityFiles f;
  f.identity_ca = f.permissions_ca = (d / "ca.pem").string();
  f.governance = (d / "governance.p7s").string();
  f.certificate = (d / role / "cert.pem").string();
  f.private_key = (d / role / "key.pem").string();
  f.permissions = (d / role / "permissions.p7s").string();
  return f;
}

void add_security_properties(DomainParticipantQos& qos, const SecurityFiles& f) {
  auto& props = qos.properties().properties();
  const std::vector<std::pair<std::string, std::string>> wanted = {
      {"dds.sec.auth.plugin", "builtin.PKI-DH"},
      {"dds.sec.auth.builtin.PKI-DH.identity_ca", "file://" + f.identity_ca},
      {"dds.sec.auth.builtin.PKI-DH.identity_certificate", "file://" + f.certificate},
      {"dds.sec.auth.builtin.PKI-DH.private_key", "file://" + f.private_key},
      {"dds.sec.access.plugin", "builtin.Access-Permissions"},
      {"dds.sec.access.builtin.Access-Permissions.permissions_ca", "file://" + f.permissions_ca},
      {"dds.sec.access.builtin.Access-Permissions.governance", "file://" + f.governance},
      {"dds.sec.access.builtin.Access-Permissions.permissions", "file://" + f.permissions},
      {"dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC"}};
  for (const auto& [name, value] : wanted) {
    bool replaced = false;
    for (auto& p : props)
      if (p.name() == name) {
        p.value(value);
        replaced = true;
      }
    if (!replaced) props.emplace_back(name, value);
  }
}

bool security_files_from_qos(const DomainParticipantQos& qos, SecurityFiles& f) {
  std::map<std::string, std::string> props;
  for (const auto& p : qos.properties().properties()) props[p.name()] = p.value();
  if (!props.count("dds.sec.auth.plugin") && !props.count("dds.sec.access.plugin")) return false;
  const auto file = [&](const std::string& name) -> std::string {
    auto it = props.find(name);
    if (it == props.end())
      throw ConfigError("participant profile", 0, name,
                        "DDS-Security is enabled but this property is missing");
    const std::string& v = it->second;
    if (v.rfind("file://", 0) == 0) return v.substr(7);
    if (v.rfind("file:", 0) == 0) return v.substr(5);
    return "";  // not a file (e.g. pkcs11:): Fast DDS checks it
  };
  if (props.count("dds.sec.auth.plugin")) {
    f.identity_ca = file("dds.sec.auth.builtin.PKI-DH.identity_ca");
    f.certificate = file("dds.sec.auth.builtin.PKI-DH.identity_certificate");
    f.private_key = file("dds.sec.auth.builtin.PKI-DH.private_key");
  }
  if (props.count("dds.sec.access.plugin")) {
    f.permissions_ca = file("dds.sec.access.builtin.Access-Permissions.permissions_ca");
    f.governance = file("dds.sec.access.builtin.Access-Permissions.governance");
    f.permissions = file("dds.sec.access.builtin.Access-Permissions.permissions");
  }
  return true;
}

namespace {

struct OpensslFree {
  void operator()(BIO* p) const { BIO_free(p); }
  void operator()(X509* p) const { X509_free(p); }
  void operator()(EVP_PKEY* p) const { EVP_PKEY_free(p); }
  void operator()(X509_STORE* p) const { X509_STORE_free(p); }
  void operator()(X509_STORE_CTX* p) const { X509_STORE_CTX_free(p); }
  void operator()(PKCS7* p) const { PKCS7_free(p); }
};
template <class T>
using Ossl = std::unique_ptr<T, OpensslFree>;

std::string openssl_errors() {
  std::string s;
  for (unsigned long e = ERR_get_error(); e != 0; e = ERR_get_error()) {
    char buf[256];
    ERR_error_string_n(e, buf, sizeof buf);
    s += s.empty() ? " (" : "; ";
    s += buf;
  }
  return s.empty() ? s : s + ")";
}

[[noreturn]] void bad(const std::string& file, const std::string& what) {
  const std::string detail = openssl_errors();
  throw ConfigError(file, 0, "", "DDS-Security: " + what + detail);
}

void check_readable(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) bad(file, "file not found");
  if (!std::filesystem::is_regular_file(file, ec)) bad(file, "not a regular file");
  if (access(file.c_str(), R_OK) != 0) bad(file, "not readable by this user");
}

Ossl<X509> read_certificate(const std::string& file) {
  Ossl<BIO> in(BIO_new_file(file.c_str(), "r"));
  if (!in) bad(file, "cannot open");
  Ossl<X509> cert(PEM_read_bio_X509(in.get(), nullptr, nullptr, nullptr));
  if (!cert) bad(file, "not a PEM X.509 certificate");
  return cert;
}

std::string asn1_time(const ASN1_TIME* t) {
  Ossl<BIO> b(BIO_new(BIO_s_mem()));
  ASN1_TIME_print(b.get(), t);
  char* data = nullptr;
  const long n = BIO_get_mem_data(b.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

void check_dates(const std::string& file, X509* cert, const std::string& what) {
  if (X509_cmp_current_time(X509_get0_notBefore(cert)) >= 0)
    bad(file, what + " is not valid yet (not before " + asn1_time(X509_get0_notBefore(cert)) + ")");
  if (X509_cmp_current_time(X509_get0_notAfter(cert)) <= 0)
    bad(file, what + " has expired (not after " + asn1_time(X509_get0_notAfter(cert)) + ")");
}

std::string subject_of(X509* cert) {
  Ossl<BIO> b(BIO_new(BIO_s_mem()));
  X509_NAME_print_ex(b.get(), X509_get_subject_name(cert), 0, XN_FLAG_RFC2253);
  char* data = nullptr;
  const long n = BIO_get_mem_data(b.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

// A distinguished name as a set of trimmed "KEY=value" parts (order and spaces after commas do not matter).
std::set<std::string> dn_parts(const std::string& dn) {
  std::set<std::string> parts;
  std::string cur;
  const auto flush = [&] {
    const auto b = cur.find_first_not_of(" \t\n"), e = cur.find_last_not_of(" \t\n");
    if (b != std::string::npos) parts.insert(cur.substr(b, e - b + 1));
    cur.clear();
  };
  for (std::size_t i = 0; i < dn.size(); ++i) {
    if (dn[i] == '\\' && i + 1 < dn.size()) {
      cur += dn[i];
      cur += dn[++i];
    } else if (dn[i] == ',' || dn[i] == '/') {
      flush();
    } else {
      cur += dn[i];
    }
  }
  flush();
  return parts;
}

// An S/MIME document signed by a certificate issued by (or equal to) the CA in `store`; its signed text.
std::string verified_document(const std::string& file, X509_STORE* store, const std::string& ca_file) {
  Ossl<BIO> in(BIO_new_file(file.c_str(), "r"));
  if (!in) bad(file, "cannot open");
  BIO* indata_raw = nullptr;
  Ossl<PKCS7> p7(SMIME_read_PKCS7(in.get(), &indata_raw));
  Ossl<BIO> indata(indata_raw);
  if (!p7) bad(file, "not an S/MIME signed document (sign it with openssl smime -sign -text)");
  Ossl<BIO> out(BIO_new(BIO_s_mem()));
  if (PKCS7_verify(p7.get(), nullptr, store, indata.get(), out.get(), PKCS7_TEXT) != 1)
    bad(file, "signature does not verify against the permissions CA " + ca_file +
                  " (signed by another CA, or altered after signing)");
  char* data = nullptr;
  const long n = BIO_get_mem_data(out.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

std::string element(const std::string& xml, const std::string& tag, std::size_t from, std::size_t to) {
  const std::string open = "<" + tag + ">", close = "</" + tag + ">";
  const auto b = xml.find(open, from);
  if (b == std::string::npos || b >= to) return "";
  const auto e = xml.find(close, b);
  if (e == std::string::npos || e > to) return "";
  std::string v = xml.substr(b + open.size(), e - b - open.size());
  const auto vb = v.find_first_not_of(" \t\r\n"), ve = v.find_last_not_of(" \t\r\n");
  return vb == std::string::npos ? "" : v.substr(vb, ve - vb + 1);
}

// xs:dateTime of a permissions validity (UTC; a zone suffix is ignored); -1 when unparsable.
long long parse_date(const std::string& s) {
  std::tm tm{};
  if (!strptime(s.c_str(), "%Y-%m-%dT%H:%M:%S", &tm)) return -1;
  return static_cast<long long>(timegm(&tm));
}

// Whether `domain` is in one of the <domains> lists between `from` and `to` (<id>N</id> or <id_range>).
bool domain_listed(const std::string& xml, std::size_t from, std::size_t to, int domain) {
  for (std::size_t d = xml.find("<domains>", from); d != std::string::npos && d < to;
       d = xml.find("<domains>", d + 1)) {
    const std::size_t end = std::min(xml.find("</domains>", d), to);
    for (std::size_t i = xml.find("<id>", d); i != std::string::npos && i < end; i = xml.find("<id>", i + 1))
      if (std::atoi(element(xml, "id", i, end).c_str()) == domain) return true;
    for (std::size_t r = xml.find("<id_range>", d); r != std::string::npos && r < end;
         r = xml.find("<id_range>", r + 1)) {
      const std::size_t re = std::min(xml.find("</id_range>", r), end);
      const std::string lo = element(xml, "min", r, re), hi = element(xml, "max", r, re);
      if ((lo.empty() || std::atoi(lo.c_str()) <= domain) && (hi.empty() || domain <= std::atoi(hi.c_str())))
        return true;
    }
  }
  return false;
}

Ossl<X509_STORE> store_with(X509* ca) {
  Ossl<X509_STORE> store(X509_STORE_new());
  X509_STORE_add_cert(store.get(), ca);
  return store;
}

}  // namespace

void validate_security_files(const SecurityFiles& f, int domain) {
  ERR_clear_error();
  for (const std::string* file :
       {&f.identity_ca, &f.certificate, &f.private_key, &f.permissions_ca, &f.governance, &f.permissions})
    if (!file->empty()) check_readable(*file);

  Ossl<X509> cert;
  if (!f.identity_ca.empty() && !f.certificate.empty()) {
    Ossl<X509> ca = read_certificate(f.identity_ca);
    check_dates(f.identity_ca, ca.get(), "the identity CA certificate");
    cert = read_certificate(f.certificate);
    check_dates(f.certificate, cert.get(), "the identity certificate " + subject_of(cert.get()));
    auto store = store_with(ca.get());
    Ossl<X509_STORE_CTX> ctx(X509_STORE_CTX_new());
    X509_STORE_CTX_init(ctx.get(), store.get(), cert.get(), nullptr);
    if (X509_verify_cert(ctx.get()) != 1) {
      const int err = X509_STORE_CTX_get_error(ctx.get());
      if (err == X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY ||
          err == X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT || err == X509_V_ERR_CERT_SIGNATURE_FAILURE ||
          err == X509_V_ERR_DEPTH_ZERO_SELF_SIGNED_CERT)
        bad(f.certificate, "the identity certificate " + subject_of(cert.get()) +
                               " is not issued by the farm CA " + f.identity_ca + " (a foreign CA?)");
      bad(f.certificate, std::string("the identity certificate does not verify against ") + f.identity_ca +
                             ": " + X509_verify_cert_error_string(err));
    }
    if (!f.private_key.empty()) {
      Ossl<BIO> in(BIO_new_file(f.private_key.c_str(), "r"));
      if (!in) bad(f.private_key, "cannot open");
      Ossl<EVP_PKEY> key(PEM_read_bio_PrivateKey(in.get(), nullptr, nullptr, nullptr));
      if (!key) bad(f.private_key, "not an unencrypted PEM private key");
      if (X509_check_private_key(cert.get(), key.get()) != 1)
        bad(f.private_key, "this private key does not belong to the certificate " + f.certificate);
    }
  }

  if (!f.permissions_ca.empty()) {
    Ossl<X509> pca = read_certificate(f.permissions_ca);
    check_dates(f.permissions_ca, pca.get(), "the permissions CA certificate");
    auto store = store_with(pca.get());
    if (!f.governance.empty()) {
      const std::string gov = verified_document(f.governance, store.get(), f.permissions_ca);
      if (gov.find("<domain_access_rules>") == std::string::npos)
        bad(f.governance, "signed, but not a governance document (no <domain_access_rules>)");
      if (domain >= 0 && !domain_listed(gov, 0, gov.size(), domain))
        bad(f.governance, "no domain rule covers domain " + std::to_string(domain));
    }
    if (!f.permissions.empty()) {
      const std::string perms = verified_document(f.permissions, store.get(), f.permissions_ca);
      if (perms.find("<permissions>") == std::string::npos)
        bad(f.permissions, "signed, but not a permissions document (no <permissions>)");
      if (cert) {
        // The grant of this certificate's subject, and its validity.
        const std::string subject = subject_of(cert.get());
        const auto want = dn_parts(subject);
        bool found = false;
        for (std::size_t g = perms.find("<grant"); g != std::string::npos; g = perms.find("<grant", g + 1)) {
          const std::size_t end = std::min(perms.find("</grant>", g), perms.size());
          if (dn_parts(element(perms, "subject_name", g, end)) != want) continue;
          found = true;
          const long long nb = parse_date(element(perms, "not_before", g, end));
          const long long na = parse_date(element(perms, "not_after", g, end));
          const long long now = static_cast<long long>(std::time(nullptr));
          if (nb < 0 || na < 0)
            bad(f.permissions, "the grant of " + subject + " has no readable validity dates");
          if (now < nb)
            bad(f.permissions, "the grant of " + subject + " is not valid yet (not_before " +
                                   element(perms, "not_before", g, end) + " UTC)");
          if (now > na)
            bad(f.permissions, "the grant of " + subject + " has expired (not_after " +
                                   element(perms, "not_after", g, end) + " UTC)");
          if (domain >= 0 && !domain_listed(perms, g, end, domain))
            bad(f.permissions,
                "the grant of " + subject + " does not allow domain " + std::to_string(domain));
          break;
        }
        if (!found)
          bad(f.permissions, "no grant for the certificate's subject '" + subject + "' of " + f.certificate +
                                 " (permissions of another role?)");
      }
    }
  }
}

Participant::Participant(const ParticipantOptions& options) : domain_(options.domain) {
  if (options.domain < 0 || options.domain > 232)
    throw ConfigError("--domain", 0, "",
                      "domain id " + std::to_string(options.domain) + " is outside 0..232");
  const std::string file = resolve_qos_file(options.qos_file);
  load_profiles_once(file);
  register_type_objects();
  auto* factory = DomainParticipantFactory::get_instance();
  DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile(options.profile, qos) != ReturnCode_t::RETCODE_OK)
    throw ConfigError(file, 0, options.profile, "no such participant profile");
  qos.name(options.name);
  // DDS-Security: --security DIR adds the properties; an XML profile may carry them instead. Either way the
  // credentials are checked here, before any DDS entity (or shared-memory file) exists.
  SecurityFiles security;
  std::string role;
  if (!options.security_dir.empty()) {
    role = options.security_role.empty() ? security_role_for(options.name) : options.security_role;
    if (role.empty())
      throw ConfigError("--security-role", 0, "",
                        "participant '" + options.name + "' has no default security role: name one");
    security = security_files(options.security_dir, role);
    add_security_properties(qos, security);
    secure_ = true;
  } else if (!options.security_role.empty()) {
    throw ConfigError("--security-role", 0, "", "needs --security DIR");
  } else {
    secure_ = security_files_from_qos(qos, security);
  }
  // WINDFDI_SECURITY_NO_PRECHECK=1 (tests only) leaves the checking to Fast DDS alone: it still refuses.
  const char* no_precheck = std::getenv("WINDFDI_SECURITY_NO_PRECHECK");
  if (secure_ && !(no_precheck && std::string(no_precheck) == "1"))
    validate_security_files(security, options.domain);
  participant_ = factory->create_participant(options.domain, qos);
  if (!participant_ && secure_)
    throw ConfigError(security.certificate.empty() ? options.security_dir : security.certificate, 0, "",
                      "DDS-Security: Fast DDS refused the credentials" +
                          (role.empty() ? std::string() : " of role '" + role + "'") +
                          " (its log above says why); participant not created");
  if (!participant_)
    throw std::runtime_error("cannot create DDS participant on domain " + std::to_string(options.domain) +
                             " with profile " + options.profile);
  spdlog::debug("participant '{}' on domain {} (profile {}, {})", options.name, options.domain,
                options.profile, file);
  if (secure_)
    spdlog::info("DDS-Security on: {}{} (authentication PKI-DH, access control, AES-GCM-GMAC)",
                 role.empty() ? "credentials of the participant profile, " : "role " + role + ", ",
                 security.certificate);
}

Participant::~Participant() {
  if (!participant_) return;
  participant_->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

Publisher* Participant::publisher() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!publisher_) {
    publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
    if (!publisher_) throw std::runtime_error("cannot create DDS publisher");
  }
  return publisher_;
}

Subscriber* Participant::subscriber() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!subscriber_) {
    subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    if (!subscriber_) throw std::runtime_error("cannot create DDS subscriber");
  }
  return subscriber_;
}

Topic* Participant::topic(const std::string& name, TypeSupport type) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = topics_.find(name);
  if (it != topics_.end()) return it->second;
  // Registering a type a second time under the same name is accepted by Fast DDS.
  if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK)
    throw std::runtime_error("cannot register DDS type " + type.get_type_name());
  Topic* t = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
  if (!t) throw std::runtime_error("cannot create DDS topic " + name);
  topics_[name] = t;
  return t;
}

std::string turbine_filter_expression(const std::vector<std::string>& turbine_ids,
                                      std::vector<std::string>& parameters) {
  std::string expr;
  parameters.clear();
  for (std::size_t i = 0; i < turbine_ids.size(); ++i) {
    expr += (i ? " OR " : "") + std::string("turbine_id = %") + std::to_string(i);
    parameters.push_back("'" + turbine_ids[i] + "'");
  }
  return expr;
}

TopicDescription* Participant::topic_for_turbines(const std::string& name, TypeSupport type,
                                                  const std::vector<std::string>& turbine_ids) {
  Topic* base = topic(name, type);
  if (turbine_ids.empty()) return base;
  if (turbine_ids.size() > 100) throw ConfigError("--turbine", 0, "", "at most 100 turbine filters");
  std::vector<std::string> params;
  const std::string expr = turbine_filter_expression(turbine_ids, params);
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string cft_name = name + "/filtered_" + std::to_string(filtered_topics_++);
  ContentFilteredTopic* cft = participant_->create_contentfilteredtopic(cft_name, base, expr, params);
  if (!cft) throw std::runtime_error("cannot create content filter '" + expr + "' on " + name);
  return cft;
}

}  // namespace windfdi::bus
