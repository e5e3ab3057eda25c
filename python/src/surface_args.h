#pragma once
// The surface sampling arguments every sampler of the module parses alike (module.cpp), for the
// part's sampler (part.cpp): grid=N or (Su, Sv), and the field names.
#include "convert.h"

#include <shapespline/core/sample_grid.h>

#include <string>
#include <utility>
#include <vector>

namespace shapespline::python {

// ValueError naming `grid` for a bad count; the default 16 x 16.
GridSpec parseSurfaceGrid(py::object grid);
// ValueError naming `fields` for an unknown name; 'point' by default, 'all' for every field.
FieldMask parseSurfaceFields(py::object fields);
// The names and fields of `mask`, in the module's order (point, du, dv, duu, duv, dvv, normal).
std::vector<std::pair<std::string, Field>> surfaceFieldsOf(FieldMask mask);

}  // namespace shapespline::python
