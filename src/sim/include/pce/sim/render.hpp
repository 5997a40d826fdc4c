// SPDX-License-Identifier: MIT
/// @file
/// A picture of a frame: a small software rasterizer that draws triangle meshes (cloth,
/// obstacles) and segments (strands) into a PNG or into RGB pixels, with no window, GPU or
/// OpenGL.
///
/// The camera looks along `view_direction` (+z up) with a 30° perspective, placed so that
/// every finite vertex is in front of it, then zoomed and centred so that the picture of
/// all meshes fills the image but for `margin` (`render_png`). A `ViewFit` fits one camera
/// to what several pictures show, so that they all show the world from the same place (the
/// frames of a movie, `render_rgb`). Surfaces are z-buffered and shaded
/// two-sided (a back face is lit like a front face) with smooth vertex normals: Lambert
/// from a headlight plus a key light from the upper left, over an ambient term. Segments
/// are depth-tested tubes `line_width` pixels wide, drawn slightly in front of surfaces at
/// the same depth so that a strand lying on cloth stays visible. The image is rendered at
/// `supersampling`² samples per pixel and averaged down (anti-aliasing).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
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

/// A fitted camera (`ViewFit`): where it is and how it projects, for one image size.
struct RenderView {
  ///@{
  /// The camera's place and its unit axes (right, up, and forward: where it looks).
  Eigen::Vector3d eye = Eigen::Vector3d::Zero(), right = Eigen::Vector3d::UnitX(), up = Eigen::Vector3d::UnitZ(),
                  forward = Eigen::Vector3d::UnitY();
  ///@}
  ///@{
  /// Screen x = cx + focal · (right · d) / z and y = cy − focal · (up · d) / z, with
  /// d = p − eye and z = forward · d, in pixels of the supersampled image.
  double focal = 1, cx = 0, cy = 0;
  ///@}
  ///@{
  /// The image the view was fitted for: `RenderOptions::width`, `height` and `supersampling`.
  int width = 0, height = 0, supersampling = 1;
  ///@}
  /// False when there was no finite point to fit: every picture is the background.
  bool valid = false;
};

/// Fits one camera to everything a series of pictures shows, in two passes over the same
/// points: first `include` every point (the camera's place, from their bounding box), then
/// `cover` every point again (the zoom and centre, from their projections); `view()` is
/// then the camera whose picture of all of them fills the image but for `margin`. Points
/// with a non-finite coordinate are skipped. `render_png` fits its camera this way to its
/// meshes' vertices.
class ViewFit {
 public:
  /// A fit for pictures of `opts`' size, view direction and margin.
  explicit ViewFit(const RenderOptions& opts);
  /// First pass: the points (one column each) join the bounding box. Throws
  /// `std::logic_error` once `cover` has been called.
  void include(const Eigen::Matrix3Xd& points);
  /// Second pass: the points' projections join the picture's extent (the first call
  /// places the camera, ending the first pass).
  void cover(const Eigen::Matrix3Xd& points);
  /// The fitted camera (`valid` false if no finite point was included).
  RenderView view() const;

 private:
  RenderOptions opts_;
  Eigen::AlignedBox3d box_;
  Eigen::AlignedBox2d screen_;
  bool placed_ = false;
  RenderView view_;
};

/// Renders `meshes` as `view` sees them into `opts.width` × `opts.height` RGB pixels, 8 bits
/// a channel, row by row from the top left (what `render_png` writes). `view` must have been
/// fitted for the same size and supersampling (`std::invalid_argument` otherwise); the
/// meshes are drawn as `render_png` draws them.
std::vector<std::uint8_t> render_rgb(const std::vector<RenderMesh>& meshes, const RenderOptions& opts,
                                     const RenderView& view);

/// Renders `meshes` and writes an RGB PNG of `opts.width` × `opts.height` to `path`.
/// Vertices with a non-finite coordinate, the triangles and segments that use them, indices
/// out of range and degenerate triangles are skipped; with nothing left to draw the image
/// is the background. Throws `std::invalid_argument` for a non-positive size and
/// `std::runtime_error("<path>: cannot write PNG")` if the file cannot be written.
void render_png(const std::string& path, const std::vector<RenderMesh>& meshes, const RenderOptions& opts = {});

}  // namespace pce::sim
