// windfdi's turbine content filter: the key read from the CDR payload, matched against ids and ranges.
#include "turbine_filter.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <sstream>

#include "turbine_selection.hpp"
#include "yaml_config.hpp"

namespace windfdi::bus {

using namespace eprosima::fastdds::dds;
using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;

namespace {

class TurbineFilter final : public IContentFilter {
 public:
  explicit TurbineFilter(TurbineSelection selection) : selection_(std::move(selection)) {}

  bool evaluate(const SerializedPayload& payload, const FilterSampleInfo&, const GUID_t&) const override {
    // Evaluated per sample per filtered reader: a view into the payload, no copy.
    std::string_view id;
    if (!turbine_id_of_payload(payload.data, payload.length, id)) {
      static std::atomic<bool> warned{false};
      if (!warned.exchange(true))
        spdlog::warn(
            "turbine filter: a sample that is not (double t, string turbine_id) in plain CDR was "
            "dropped (encapsulation {:#x}{:02x})",
            payload.length > 1 ? payload.data[0] : 0, payload.length > 1 ? payload.data[1] : 0);
      return false;
    }
    return selection_.contains(id);
  }

 private:
  TurbineSelection selection_;
};

}  // namespace

std::string turbine_filter_expression(const std::vector<std::string>& turbine_ids) {
  std::string expr;
  for (const auto& value : turbine_ids) expr += (expr.empty() ? "" : " ") + value;
  return expr;
}

bool turbine_id_of_payload(const unsigned char* data, std::size_t length, std::string_view& turbine_id) {
  // Encapsulation (2 bytes representation, 2 options), then the double t at 0 and the string's length at 8
  // (CDR and CDR2 align alike here), counting its terminating NUL, then its characters.
  constexpr std::size_t kHeader = 4, kLength = kHeader + 8, kChars = kLength + 4;
  if (length < kChars || data[0] != 0) return false;
  const unsigned char representation = data[1];
  bool little_endian;
  if (representation == 0x00 || representation == 0x06)  // CDR_BE, PLAIN_CDR2_BE
    little_endian = false;
  else if (representation == 0x01 || representation == 0x07)  // CDR_LE, PLAIN_CDR2_LE
    little_endian = true;
  else
    return false;
  const unsigned char* l = data + kLength;
  const uint32_t size =
      little_endian ? (uint32_t(l[0]) | uint32_t(l[1]) << 8 | uint32_t(l[2]) << 16 | uint32_t(l[3]) << 24)
                    : (uint32_t(l[3]) | uint32_t(l[2]) << 8 | uint32_t(l[1]) << 16 | uint32_t(l[0]) << 24);
  if (size < 1 || size > length - kChars || data[kChars + size - 1] != 0) return false;
  turbine_id = std::string_view(reinterpret_cast<const char*>(data + kChars), size - 1);
  return true;
}

TurbineFilterFactory& TurbineFilterFactory::instance() {
  static TurbineFilterFactory factory;
  return factory;
}

ReturnCode TurbineFilterFactory::create_content_filter(const char*, const char*, const TopicDataType*,
                                                       const char* filter_expression, const ParameterSeq&,
                                                       IContentFilter*& filter_instance) {
  // No expression: only the parameters change, and this filter has none.
  if (!filter_expression) return filter_instance ? ReturnCode::RETCODE_OK : ReturnCode::RETCODE_BAD_PARAMETER;
  std::vector<std::string> values;
  std::istringstream in(filter_expression);
  for (std::string value; in >> value;) values.push_back(value);
  if (values.empty()) return ReturnCode::RETCODE_BAD_PARAMETER;
  try {
    TurbineSelection selection(values);
    // Fast DDS hands back the filter it made before when the expression changes: replace it.
    delete static_cast<TurbineFilter*>(filter_instance);
    filter_instance = new TurbineFilter(std::move(selection));
  } catch (const ConfigError&) {
    return ReturnCode::RETCODE_BAD_PARAMETER;
  }
  return ReturnCode::RETCODE_OK;
}

ReturnCode TurbineFilterFactory::delete_content_filter(const char*, IContentFilter* filter_instance) {
  delete static_cast<TurbineFilter*>(filter_instance);
  return ReturnCode::RETCODE_OK;
}

}  // namespace windfdi::bus
