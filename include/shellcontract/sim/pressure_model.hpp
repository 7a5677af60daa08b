// Which pressure force a run applies, as plain data. A leaf: the run options (sim/config.hpp)
// include this, not the pressure module (pressure.hpp).
#pragma once

namespace shellcontract {

/// energy: f_i = -(P/6) sum_{j ni i} N_j = -P dV/dx_i (default; no net force, work = -P dV).
/// paper:  f_i = -P nhat_i sum_{j ni i} A_j / 3 with the area-weighted unit vertex normal
///         (paper eq. for Step 1; same direction, larger magnitude on coarse meshes).
enum class PressureModel { EnergyConsistent, Paper };

}  // namespace shellcontract
