// ContactSheet: shaded renders of one posed model, deformed by several methods at several clip
// frames, laid out as a grid (sweepctl sheet and the daemon's ContactSheetRequest: one row per
// frame, one column per method; sheet --video: one row per video frame) for people to compare
// the methods by eye.
//
// Each cell is cell_width × cell_height pixels: a white caption band on top (method; frame and
// the worst edge stretch from metrics::QualityMeter, as `sweepctl metrics` reports it) and the
// render below it (gpu::PreviewRenderer), optionally coloured by edge stretch
// (gpu/sheet/stretch_heat.h).
// Cameras (gpu::box_camera), one per frame and shared by the methods of its row:
//   whole body  looking at the centre of the body's bounding box at that frame (linear blend
//               skinning), all framing one box: the largest extent of the body along the view's
//               axes over all frames, 5 % to spare, so the body has the same scale in every cell;
//   focus       looking at one joint (focus_joint), framing a cube of half side 0.16 × the rest
//               model's height.
// The eye looks at the body's front (its rest front, found from its arms or thighs whichever way
// it was modelled, turned as the pelvis turned at that frame; then turned about the vertical by
// azimuth_degrees towards the body's left, raised by elevation_degrees).
//
// Inputs: a SheetModel (the bound model, its runtime and the pose of a clip frame); SheetOptions
//   (methods, frames, cell size, focus, heat); the PairSource of sweep+features (null: the CPU
//   reference); a DrawCell, where the cells are rendered — sweepctl's own gpu::Context on its
//   thread, or the daemon's GPU thread (server/services/contact_sheet_service.h). The
//   constructor runs the framing pass (one LBS deformation per frame, no GL). render_row(i,
//   rgba, row) renders frame frames[i] into row `row` of a picture width() pixels wide (rgba:
//   width() × rows × cell_height × 4 bytes, row 0 at the top).
// Every cell is shaded with the normals of its posed surface (the runtime's WeldedNormals), for
// every method alike: LBS's and DQS's own skinned normals would hide their creases.
// edge_ratios(): each rendered cell's shortest and longest edge as l / l_rest, in order.
// Use on one thread; DrawCell is called on it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "deform/binding/bound_model.h"
#include "gpu/camera.h"
#include "gpu/preview_renderer.h"
#include "gpu/sheet/deform_with.h"
#include "gpu/sheet/stretch_heat.h"
#include "metrics/quality_metrics.h"

namespace sweepd::sheet {

// A close-up's joint by role name: shoulder_l, elbow_l, wrist_l, hip_l, knee_l, ankle_l (and
// _r), neck, chest, pelvis.
const std::vector<std::string>& focus_names();
// The joint of that role in the rig map; throws std::invalid_argument when the model lacks it.
int focus_joint(const deform::RigMap& rig, const std::string& name);

struct SheetOptions {
  std::vector<deform::MethodChoice> methods;
  std::vector<int> frames;
  int cell_width = 240, cell_height = 320;
  std::string focus;          // empty: the whole body
  bool heat = false;          // colour by edge stretch
  float heat_full_scale = 1;  // the stretch shown red (1 = 100 %)
  float azimuth_degrees = 0;  // 0: the body's front; 90: its left side
  float elevation_degrees = 0;

  // The picture's pixels: cells × methods × frames.
  std::uint64_t pixel_count() const {
    return static_cast<std::uint64_t>(cell_width) * cell_height * methods.size() * frames.size();
  }
};

// What a sheet poses. `pose` gives the pose of a clip frame (throws for a frame it lacks).
struct SheetModel {
  const deform::BoundModel& bound;
  const deform::ModelRuntime& runtime;
  std::function<deform::Pose(int frame)> pose;
};

// A cell's shortest and longest edge as length ratios l / l_rest (squash, stretch).
struct EdgeRatios {
  double shortest = 1.0, longest = 1.0;
  // The largest |l / l_rest - 1|: protocol 1.11-1.15's ContactSheet.worst_stretch.
  double largest_change() const { return std::max(longest - 1.0, 1.0 - shortest); }
};

// A whole sheet as sweepctl writes it and the daemon sends it (ContactSheet, protocol 1.11).
struct SheetPicture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> png;        // RGBA PNG file bytes
  std::vector<EdgeRatios> edge_ratios;  // each cell's, row by row (frame, then method)
  std::string renderer;                 // GL_RENDERER of the context that drew it
};

// Renders one cell's mesh as gpu::PreviewRenderer::render does, into `rgba` (width × height × 4).
using DrawCell =
    std::function<void(const gpu::PreviewMesh& mesh, const gpu::PreviewOptions& options,
                       std::span<std::uint8_t> rgba)>;

class ContactSheet {
 public:
  static constexpr int kSmallestCell = 64;   // pixels, either side
  static constexpr int kLargestCell = 2048;  // pixels, either side
  static constexpr std::size_t kMostRows = 32;
  ContactSheet(SheetModel model, const SheetOptions& options, PairSource* pairs, DrawCell draw);

  const SheetOptions& options() const { return options_; }
  int width() const { return options_.cell_width * static_cast<int>(options_.methods.size()); }
  void render_row(std::size_t frame_index, std::span<std::uint8_t> rgba, int row);
  const std::vector<EdgeRatios>& edge_ratios() const { return edge_ratios_; }

 private:
  void render_cell(std::size_t frame_index, std::size_t method, std::span<std::uint8_t> rgba,
                   int row);

  SheetModel model_;
  SheetOptions options_;
  PairSource* pairs_;
  DrawCell draw_;
  metrics::QualityMeter meter_;
  StretchHeat heat_;
  deform::DeformContext deform_context_;
  int caption_scale_ = 1, caption_height_ = 0;
  std::vector<gpu::Camera> cameras_;  // per frame
  std::vector<glm::vec3> positions_, normals_, colours_;
  std::vector<deform::FloatLanes> normal_sums_;  // WeldedNormals' scratch
  std::vector<std::uint8_t> cell_;  // the render, cell_width × (cell_height − caption) × 4
  std::vector<EdgeRatios> edge_ratios_;
};

// The whole grid, row by row, as a PNG (io::encode_png), with each cell's edge ratios and
// `renderer`, the GL_RENDERER of the context that DrawCell draws with.
SheetPicture draw_picture(ContactSheet& contact, std::string renderer);

}  // namespace sweepd::sheet
