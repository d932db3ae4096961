#pragma once
// The whole pipeline on one screen. Each stage is a free function from plain data to plain
// data; see DESIGN.md section 3.
//
//   Scene      importScene(path, ImportOptions, Diagnostics&)                  io/import.h
//   PartSet    buildParts(const Scene&, PartOptions, Diagnostics&)             geometry/parts.h
//   Solution   solveRadiosity(const Scene&, const PartSet&, SolverOptions, ...) radiosity/solver.h
//   VertexBake bakeVertices(const Scene&, const Solution&, ...)                 bake/vertex_bake.h
//   void       writeOutputs(...)                                                export/
#include "io/import.h"
