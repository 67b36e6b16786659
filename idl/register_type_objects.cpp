// Registers the TypeObjects of every windfdi topic type once (needed by the SQL content filter).
#include <mutex>

#include "ControlConfigurationTypeObject.h"
#include "EstimatesTypeObject.h"
#include "FaultAckTypeObject.h"
#include "FaultReportTypeObject.h"
#include "LidarFrameTypeObject.h"
#include "ServiceHealthTypeObject.h"
#include "TurbineFrameTypeObject.h"
#include "TypesTypeObject.h"

namespace windfdi {

void register_type_objects() {
  static std::once_flag once;
  std::call_once(once, [] {
    registerTypesTypes();
    registerTurbineFrameTypes();
    registerLidarFrameTypes();
    registerEstimatesTypes();
    registerFaultReportTypes();
    registerServiceHealthTypes();
    registerControlConfigurationTypes();
    registerFaultAckTypes();
  });
}

}  // namespace windfdi
