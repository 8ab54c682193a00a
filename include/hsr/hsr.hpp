#pragma once
// The whole public API in one include: `#include <hsr/hsr.hpp>`. Each header below also stands
// alone, and a program that wants one part includes that part only.

#include <string_view>

#include "hsr/algorithms.hpp"  // the registry: every algorithm, its capabilities and limits
#include "hsr/bsp.hpp"         // a 3D BSP tree built once, rendered from any viewpoint
#include "hsr/camera.hpp"      // look-at + perspective or orthographic; intrinsics and poses
#include "hsr/clipping.hpp"    // Weiler–Atherton: A∩B, A∪B, A−B, B−A of polygonal regions
#include "hsr/compare.hpp"     // every algorithm on one scene, side by side
#include "hsr/doom.hpp"        // Doom maps, their 2D BSP, the column view
#include "hsr/error.hpp"       // hsr::Error, the one error type
#include "hsr/explain.hpp"     // an algorithm's steps as pictures
#include "hsr/frontend.hpp"    // every option of the CLI, Python and the web page, checked once
#include "hsr/gl.hpp"          // the GL-style facade (depth test, mask, cull, polygon mode)
#include "hsr/io.hpp"          // scene sources and writers (PNG, NPY, JSON)
#include "hsr/line_drawing.hpp"  // hidden-line drawings as strokes, SVG and PDF
#include "hsr/output.hpp"        // outputs that are never half-written
#include "hsr/ray_scene.hpp"     // ray queries: nearest hit per ray
#include "hsr/render.hpp"        // render(): scene + camera + options -> Frame
#include "hsr/roberts.hpp"       // Roberts' visible edges as segments
#include "hsr/scene.hpp"         // polygons with stable ids, materials, objects
#include "hsr/stats.hpp"         // what one render did, counted and timed
#include "hsr/visible_set.hpp"   // the visible set as exact 2D polygons

namespace hsr {

// The library's version ("0.1.0"), as the CMake project states it.
std::string_view version();

}  // namespace hsr
