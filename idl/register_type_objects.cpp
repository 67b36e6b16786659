// Registers the TypeObjects of the idl/ topic types once (the SQL content filter of the sensor streams needs
// them; the services' estimate topics are not content-filtered).
#include <mutex>

#include "ControlConfigurationTypeObject.h"
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
    registerFaultReportTypes();
    registerServiceHealthTypes();
    registerControlConfigurationTypes();
    registerFaultAckTypes();
  });
}

}  // namespace windfdi
