// windfdi's own DDS content filter class: selects samples by turbine id, read straight from the payload.
#pragma once

#include <fastdds/dds/topic/IContentFilterFactory.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace windfdi::bus {

/// The filter class name readers announce. Every windfdi participant registers the factory, so a writer
/// (the plant's frames) evaluates its remote readers' filters with it; a writer without it sends every
/// sample and the reader evaluates the same filter.
constexpr const char* kTurbineFilterClass = "WINDFDI_TURBINE";

/// The filter expression: the --turbine values (ids and FIRST..LAST ranges) separated by spaces.
std::string turbine_filter_expression(const std::vector<std::string>& turbine_ids);

/// The turbine id of a serialized sample whose type starts `double t; string turbine_id;` (TurbineFrame,
/// LidarFrame: every topic with TopicTraits::writer_filtering; ControlConfiguration too), plain CDR or CDR2
/// in either byte order; false when the payload is not such a sample. The id is a view into `data`.
bool turbine_id_of_payload(const unsigned char* data, std::size_t length, std::string_view& turbine_id);

/// Fast DDS 2.9's built-in SQL filter builds a DynamicData of the whole sample for every evaluation
/// (a TurbineFrame block of 10 samples, with exceptions thrown and caught inside): with the four services of
/// two hosts filtering, the plant spent a core on it at 40 turbines. This filter reads only the key.
class TurbineFilterFactory : public eprosima::fastdds::dds::IContentFilterFactory {
 public:
  /// The process-wide factory (it must outlive every participant that registered it).
  static TurbineFilterFactory& instance();

  ReturnCode_t create_content_filter(const char* filter_class_name, const char* type_name,
                                     const eprosima::fastdds::dds::TopicDataType* data_type,
                                     const char* filter_expression, const ParameterSeq& filter_parameters,
                                     eprosima::fastdds::dds::IContentFilter*& filter_instance) override;
  ReturnCode_t delete_content_filter(const char* filter_class_name,
                                     eprosima::fastdds::dds::IContentFilter* filter_instance) override;
};

}  // namespace windfdi::bus
