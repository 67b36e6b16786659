// DDS-Security credentials by role: the files make_credentials.sh lays out, checked with OpenSSL and tinyxml2
// before any DDS entity exists (Fast DDS would refuse them later with a less helpful message).
#include "security.hpp"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "windfdi_services.hpp"
#include "yaml_config.hpp"

namespace windfdi::bus {

using namespace eprosima::fastdds::dds;

// ---------------------------------------------------------------------------------------------------------
// DDS-Security: credentials by role, checked before the participant exists.

std::string security_role_for(const std::string& participant_name) {
  const std::string prefix = "windfdi-";
  if (participant_name.rfind(prefix, 0) != 0) return "";
  std::string rest = participant_name.substr(prefix.size());
  for (auto& c : rest)
    if (c == '-') c = '_';
  if (rest == "farm" || rest == "farm_ack") return "farm";
  static const std::set<std::string> roles = {"plant", "arbiter", WINDFDI_DIAGNOSTIC_SERVICE_NAMES};
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

// The trimmed text of the first `tag` element anywhere below `parent` ("" when there is none).
std::string text_below(const tinyxml2::XMLElement* parent, const char* tag) {
  if (!parent) return "";
  for (const auto* e = parent->FirstChildElement(); e; e = e->NextSiblingElement()) {
    if (std::strcmp(e->Name(), tag) == 0) {
      std::string v = e->GetText() ? e->GetText() : "";
      const auto vb = v.find_first_not_of(" \t\r\n"), ve = v.find_last_not_of(" \t\r\n");
      return vb == std::string::npos ? "" : v.substr(vb, ve - vb + 1);
    }
    if (std::string t = text_below(e, tag); !t.empty()) return t;
  }
  return "";
}

// Every element named `tag` anywhere below `parent`, in document order.
void elements_below(const tinyxml2::XMLElement* parent, const char* tag,
                    std::vector<const tinyxml2::XMLElement*>& out) {
  for (const auto* e = parent ? parent->FirstChildElement() : nullptr; e; e = e->NextSiblingElement()) {
    if (std::strcmp(e->Name(), tag) == 0) out.push_back(e);
    elements_below(e, tag, out);
  }
}

// xs:dateTime of a permissions validity (UTC; a zone suffix is ignored); -1 when unparsable.
long long parse_date(const std::string& s) {
  std::tm tm{};
  if (!strptime(s.c_str(), "%Y-%m-%dT%H:%M:%S", &tm)) return -1;
  return static_cast<long long>(timegm(&tm));
}

// Whether `domain` is in one of the <domains> lists below `parent` (<id>N</id> or <id_range>).
bool domain_listed(const tinyxml2::XMLElement* parent, int domain) {
  std::vector<const tinyxml2::XMLElement*> lists;
  elements_below(parent, "domains", lists);
  for (const auto* d : lists)
    for (const auto* e = d->FirstChildElement(); e; e = e->NextSiblingElement()) {
      if (std::strcmp(e->Name(), "id") == 0 && e->GetText() && std::atoi(e->GetText()) == domain) return true;
      if (std::strcmp(e->Name(), "id_range") == 0) {
        const std::string lo = text_below(e, "min"), hi = text_below(e, "max");
        if ((lo.empty() || std::atoi(lo.c_str()) <= domain) &&
            (hi.empty() || domain <= std::atoi(hi.c_str())))
          return true;
      }
    }
  return false;
}

// The signed document parsed; its `dds` root's child `section` (governance: domain_access_rules,
// permissions: permissions), or a ConfigError naming the file.
const tinyxml2::XMLElement* section_of(tinyxml2::XMLDocument& doc, const std::string& text,
                                       const std::string& file, const char* section, const char* what) {
  if (doc.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS)
    bad(file, std::string("signed, but its XML does not parse: ") + doc.ErrorStr());
  const auto* root = doc.FirstChildElement("dds");
  const auto* e = root ? root->FirstChildElement(section) : nullptr;
  if (!e) bad(file, std::string("signed, but not a ") + what + " document (no <dds><" + section + ">)");
  return e;
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
      tinyxml2::XMLDocument doc;
      const auto* rules = section_of(doc, gov, f.governance, "domain_access_rules", "governance");
      if (domain >= 0 && !domain_listed(rules, domain))
        bad(f.governance, "no domain rule covers domain " + std::to_string(domain));
    }
    if (!f.permissions.empty()) {
      const std::string perms = verified_document(f.permissions, store.get(), f.permissions_ca);
      tinyxml2::XMLDocument doc;
      const auto* permissions = section_of(doc, perms, f.permissions, "permissions", "permissions");
      if (cert) {
        // The grant of this certificate's subject, and its validity.
        const std::string subject = subject_of(cert.get());
        const auto want = dn_parts(subject);
        bool found = false;
        for (const auto* g = permissions->FirstChildElement("grant"); g; g = g->NextSiblingElement("grant")) {
          if (dn_parts(text_below(g, "subject_name")) != want) continue;
          found = true;
          const long long nb = parse_date(text_below(g, "not_before"));
          const long long na = parse_date(text_below(g, "not_after"));
          const long long now = static_cast<long long>(std::time(nullptr));
          if (nb < 0 || na < 0)
            bad(f.permissions, "the grant of " + subject + " has no readable validity dates");
          if (now < nb)
            bad(f.permissions, "the grant of " + subject + " is not valid yet (not_before " +
                                   text_below(g, "not_before") + " UTC)");
          if (now > na)
            bad(f.permissions, "the grant of " + subject + " has expired (not_after " +
                                   text_below(g, "not_after") + " UTC)");
          if (domain >= 0 && !domain_listed(g, domain))
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

}  // namespace windfdi::bus
