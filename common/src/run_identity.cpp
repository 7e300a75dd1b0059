/// @file run_identity.cpp
/// Run identity (run_identity.hpp).
#include "common/run_identity.hpp"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <toml++/toml.h>

#include "common/schema.hpp"
#include "common/status.hpp"

namespace common {
namespace {
constexpr std::uint64_t kFnvOffset = 14695981039346656037ull, kFnvPrime = 1099511628211ull;

std::uint64_t fnv1a(std::uint64_t h, const unsigned char* p, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * kFnvPrime;
  return h;
}
std::string hex16(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

bool excluded_key(const std::string& key, const std::vector<std::string>& excluded) {
  for (const auto& e : excluded) {
    if (!e.empty() && e.back() == '.' ? key.rfind(e, 0) == 0 : key == e) return true;
  }
  return false;
}

void flatten(const toml::table& t, const std::string& prefix, std::map<std::string, std::string>& out) {
  for (const auto& [k, node] : t) {
    const std::string key = prefix + std::string(k.str());
    if (const toml::table* sub = node.as_table()) {
      flatten(*sub, key + ".", out);
    } else if (const toml::array* arr = node.as_array(); arr && arr->is_array_of_tables() && !arr->empty()) {
      for (std::size_t i = 0; i < arr->size(); ++i)
        flatten(*(*arr)[i].as_table(), key + "[" + std::to_string(i) + "].", out);
    } else {
      std::ostringstream os;
      node.visit([&](const auto& v) { os << v; });
      out[key] = os.str();
    }
  }
}
}  // namespace

std::string file_fingerprint(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(path + ": cannot read input file: " + std::strerror(errno));
  std::uint64_t h = kFnvOffset, size = 0;
  std::vector<unsigned char> buf(1 << 20);
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) {
    h = fnv1a(h, buf.data(), n);
    size += n;
  }
  const bool err = std::ferror(f);
  std::fclose(f);
  if (err) throw InputError(path + ": read error while hashing the input file");
  return std::to_string(size) + " bytes, fnv1a64 " + hex16(h);
}

std::string RunIdentity::text() const {
  std::string s;
  for (const auto& [k, v] : parts) s += k + " = " + v + "\n";
  return s;
}

std::string RunIdentity::digest() const {
  const std::string t = text();
  return hex16(fnv1a(kFnvOffset, reinterpret_cast<const unsigned char*>(t.data()), t.size()));
}

RunIdentity RunIdentity::parse(const std::string& text) {
  RunIdentity id;
  std::istringstream is(text);
  for (std::string line; std::getline(is, line);) {
    const auto eq = line.find(" = ");
    if (eq != std::string::npos) id.parts[line.substr(0, eq)] = line.substr(eq + 3);
  }
  return id;
}

std::string RunIdentity::differences(const RunIdentity& a, const std::string& label_a, const RunIdentity& b,
                                     const std::string& label_b) {
  std::string out;
  auto add = [&](const std::string& key, const std::string* va, const std::string* vb) {
    if (!out.empty()) out += "; ";
    out += key + ": " + label_a + " " + (va ? *va : std::string("(absent)")) + ", " + label_b + " " +
           (vb ? *vb : std::string("(absent)"));
  };
  for (const auto& [k, v] : a.parts) {
    auto it = b.parts.find(k);
    if (it == b.parts.end()) add(k, &v, nullptr);
    else if (it->second != v) add(k, &v, &it->second);
  }
  for (const auto& [k, v] : b.parts)
    if (!a.parts.count(k)) add(k, nullptr, &v);
  return out;
}

RunIdentity RunIdentity::without(const std::vector<std::string>& excluded) const {
  RunIdentity id;
  for (const auto& [k, v] : parts)
    if (!excluded_key(k, excluded)) id.parts.emplace(k, v);
  return id;
}

RunIdentity run_identity(const Scene& sc, const std::vector<std::string>& excluded,
                         const std::vector<std::string>& file_keys) {
  toml::table t;
  try {
    t = toml::parse(sc.to_toml());
  } catch (const toml::parse_error& e) {
    throw InputError(sc.source() + ": cannot re-read the resolved scene: " + std::string(e.description()));
  }
  RunIdentity id;
  std::map<std::string, std::string> all;
  flatten(t, "", all);
  for (auto& [k, v] : all)
    if (!excluded_key(k, excluded)) id.parts[k] = v;
  for (const auto& k : file_keys) {
    auto it = id.parts.find(k);
    if (it == id.parts.end()) continue;
    const std::string path = sc.string(k);
    try {
      it->second = path.empty() ? std::string("(none)") : file_fingerprint(path);
    } catch (const InputError&) {
      it->second = "(unreadable)";  // the reader reports it, naming the file
    }
  }
  return id;
}

}  // namespace common
