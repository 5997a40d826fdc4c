// SPDX-License-Identifier: MIT
/// @file
/// A picture of a frame: a small software rasterizer that draws triangle meshes (cloth,
/// obstacles) and segments (strands) into a PNG, with no window, GPU or OpenGL.
///
/// The camera looks along `view_direction` (+z up) with a 30° perspective, placed so that
/// every finite vertex is in front of it, then zoomed and centred so that the picture of
/// all meshes fills the image but for `margin`. Surfaces are z-buffered and shaded
/// two-sided (a back face is lit like a front face) with smooth vertex normals: Lambert
/// from a headlight plus a key light from the upper left, over an ambient term. Segments
/// are depth-tested tubes `line_width` pixels wide, drawn slightly in front of surfaces at
/// the same depth so that a strand lying on cloth stays visible. The image is rendered at
/// `supersampling`² samples per pixel and averaged down (anti-aliasing).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace pce::sim {

/// One mesh to draw, in world coordinates, with its colour.
struct RenderMesh {
  Eigen::Matrix3Xd positions;                                   ///< one column per vertex
  Eigen::Matrix3Xi triangles;                                   ///< drawn as shaded surfaces
  Eigen::Matrix2Xi segments;                                    ///< drawn as tubes
  Eigen::Vector3f color = Eigen::Vector3f(0.8f, 0.35f, 0.25f);  ///< linear RGB in [0, 1]
};

/// Image size, camera and style of `render_png`.
struct RenderOptions {
  ///@{
  int width = 960, height = 720;  ///< pixels
  ///@}
  /// Where the camera looks (need not be unit); looking slightly down from the front right.
  Eigen::Vector3d view_direction = Eigen::Vector3d(-1.0, -2.0, -0.9).normalized();
  double margin = 0.05;  ///< empty border on each side, as a fraction of the image size
  Eigen::Vector3f background = Eigen::Vector3f(0.92f, 0.92f, 0.93f);  ///< light grey
  double line_width = 3.0;                                            ///< segment tubes' width, pixels
  int supersampling = 2;                                              ///< samples per pixel along each axis, 1 to 4
};

/// Renders `meshes` and writes an RGB PNG of `opts.width` × `opts.height` to `path`.
/// Vertices with a non-finite coordinate, the triangles and segments that use them, indices
/// out of range and degenerate triangles are skipped; with nothing left to draw the image
/// is the background. Throws `std::invalid_argument` for a non-positive size and
/// `std::runtime_error("<path>: cannot write PNG")` if the file cannot be written.
void render_png(const std::string& path, const std::vector<RenderMesh>& meshes, const RenderOptions& opts = {});

}  // namespace pce::sim
