/// @file json_writer.cpp
/// Implementation of analysis/json_writer.hpp (the header states the contract, and for physics the equations and sources).
#include "analysis/json_writer.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace analysis {

std::string JsonWriter::quote(const std::string& s) {
  std::string o = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      case '\r': o += "\\r"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          o += buf;
        } else {
          o += static_cast<char>(c);
        }
    }
  }
  return o + "\"";
}

std::string JsonWriter::number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream o;
  o.precision(17);
  o << v;
  return o.str();
}

void JsonWriter::key_prefix(const std::string& key) {
  if (!first_.empty()) {
    if (!first_.back()) out_ += ",";
    first_.back() = false;
    out_ += "\n" + std::string(2 * first_.size(), ' ');
  }
  if (!key.empty()) out_ += quote(key) + ": ";
}

JsonWriter& JsonWriter::begin_object(const std::string& key) {
  key_prefix(key);
  out_ += "{";
  first_.push_back(true);
  return *this;
}
JsonWriter& JsonWriter::end_object() {
  const bool empty = first_.back();
  first_.pop_back();
  if (!empty) out_ += "\n" + std::string(2 * first_.size(), ' ');
  out_ += "}";
  return *this;
}
JsonWriter& JsonWriter::begin_array(const std::string& key) {
  key_prefix(key);
  out_ += "[";
  first_.push_back(true);
  return *this;
}
JsonWriter& JsonWriter::end_array() {
  const bool empty = first_.back();
  first_.pop_back();
  if (!empty) out_ += "\n" + std::string(2 * first_.size(), ' ');
  out_ += "]";
  return *this;
}
JsonWriter& JsonWriter::value(const std::string& key, double v) {
  key_prefix(key);
  out_ += number(v);
  return *this;
}
JsonWriter& JsonWriter::value(const std::string& key, std::optional<double> v) {
  return v ? value(key, *v) : null(key);
}
JsonWriter& JsonWriter::value(const std::string& key, long long v) {
  key_prefix(key);
  out_ += std::to_string(v);
  return *this;
}
JsonWriter& JsonWriter::value(const std::string& key, bool v) {
  key_prefix(key);
  out_ += v ? "true" : "false";
  return *this;
}
JsonWriter& JsonWriter::value(const std::string& key, const std::string& v) {
  key_prefix(key);
  out_ += quote(v);
  return *this;
}
JsonWriter& JsonWriter::value(const std::string& key, const Eigen::Vector3d& v) {
  key_prefix(key);
  out_ += "[" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
  return *this;
}
JsonWriter& JsonWriter::value(const std::string& key, const std::vector<std::string>& v) {
  key_prefix(key);
  out_ += "[";
  for (std::size_t i = 0; i < v.size(); ++i) out_ += (i ? ", " : "") + quote(v[i]);
  out_ += "]";
  return *this;
}
JsonWriter& JsonWriter::null(const std::string& key) {
  key_prefix(key);
  out_ += "null";
  return *this;
}

}  // namespace analysis
