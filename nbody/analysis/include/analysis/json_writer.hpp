/// @file json_writer.hpp
/// A minimal JSON emitter for the analysis summary (objects, arrays, strings, numbers; non-finite
/// numbers become null). Local helper: common/ has no JSON writer.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace analysis {

class JsonWriter {
 public:
  JsonWriter& begin_object(const std::string& key = {});
  JsonWriter& end_object();
  JsonWriter& begin_array(const std::string& key = {});
  JsonWriter& end_array();
  JsonWriter& value(const std::string& key, double v);
  JsonWriter& value(const std::string& key, std::optional<double> v);
  JsonWriter& value(const std::string& key, long long v);
  JsonWriter& value(const std::string& key, bool v);
  JsonWriter& value(const std::string& key, const std::string& v);
  JsonWriter& value(const std::string& key, const char* v) { return value(key, std::string(v)); }
  JsonWriter& value(const std::string& key, const Eigen::Vector3d& v);
  JsonWriter& value(const std::string& key, const std::vector<std::string>& v);
  JsonWriter& null(const std::string& key);
  /// The document (call after the outermost end_object).
  std::string str() const { return out_ + "\n"; }

  static std::string quote(const std::string& s);
  static std::string number(double v);

 private:
  void key_prefix(const std::string& key);
  std::string out_;
  std::vector<bool> first_;  ///< per open container: no element written yet
};

}  // namespace analysis
