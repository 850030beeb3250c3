#include "gpu/sheet/contact_sheet.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <stdexcept>
#include <utility>

#include "gpu/sheet/caption_text.h"
#include "io/png/png_write.h"

namespace sweepd::sheet {

namespace {

// Every role a close-up can frame, with the part named in the refusal when it is absent.
struct FocusRole {
  const char* part;
  std::function<int(const deform::RigMap&)> joint;
};

const std::map<std::string, FocusRole>& focus_roles() {
  using R = const deform::RigMap&;
  static const std::map<std::string, FocusRole> roles = {
      {"shoulder_l", {"left arm", [](R r) { return r.left_arm.upper; }}},
      {"shoulder_r", {"right arm", [](R r) { return r.right_arm.upper; }}},
      {"elbow_l", {"left arm", [](R r) { return r.left_arm.lower; }}},
      {"elbow_r", {"right arm", [](R r) { return r.right_arm.lower; }}},
      {"wrist_l", {"left arm", [](R r) { return r.left_arm.hand; }}},
      {"wrist_r", {"right arm", [](R r) { return r.right_arm.hand; }}},
      {"hip_l", {"left leg", [](R r) { return r.left_leg.upper; }}},
      {"hip_r", {"right leg", [](R r) { return r.right_leg.upper; }}},
      {"knee_l", {"left leg", [](R r) { return r.left_leg.lower; }}},
      {"knee_r", {"right leg", [](R r) { return r.right_leg.lower; }}},
      {"ankle_l", {"left leg", [](R r) { return r.left_leg.foot; }}},
      {"ankle_r", {"right leg", [](R r) { return r.right_leg.foot; }}},
      {"neck", {"head", [](R r) { return r.neck.chain.empty() ? -1 : r.neck.chain.front(); }}},
      {"chest", {"torso", [](R r) { return r.torso.chest(); }}},
      {"pelvis", {"torso", [](R r) { return r.torso.pelvis(); }}}};
  return roles;
}

constexpr float kFocusRadiusPerHeight = 0.16f;
// Room around the whole body: 5 % of its extent on each side.
constexpr float kBodyMargin = 1.05f;
constexpr std::array<std::uint8_t, 3> kCaptionInk{30, 30, 36};

float rest_height(std::span<const glm::vec3> positions) {
  float low = positions.front().y, high = low;
  for (const glm::vec3& p : positions) low = std::min(low, p.y), high = std::max(high, p.y);
  return high - low;
}

// The eye's direction from the body at this frame: the body's rest front (found from its arms or
// thighs, deform::rest_body_axes, not assumed +Z: a character modelled facing +X was drawn from
// its side) turned as the pelvis turned, flattened onto the ground, then turned by azimuth and
// raised by elevation.
glm::vec3 eye_direction(const glm::mat4& pelvis_world, const glm::mat4& pelvis_rest,
                        const glm::vec3& rest_front, float azimuth_degrees,
                        float elevation_degrees) {
  glm::vec3 front = glm::mat3(pelvis_world) * glm::inverse(glm::mat3(pelvis_rest)) * rest_front;
  front.y = 0.0f;
  front = glm::length(front) > 1e-3f ? glm::normalize(front) : glm::vec3(0.0f, 0.0f, 1.0f);
  const glm::vec3 left = glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), front);
  const float azimuth = glm::radians(azimuth_degrees);
  const float elevation = glm::radians(elevation_degrees);
  const glm::vec3 around = std::cos(azimuth) * front + std::sin(azimuth) * left;
  return std::cos(elevation) * around + std::sin(elevation) * glm::vec3(0.0f, 1.0f, 0.0f);
}

}  // namespace

const std::vector<std::string>& focus_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const auto& [name, role] : focus_roles()) all.push_back(name);
    return all;
  }();
  return names;
}

int focus_joint(const deform::RigMap& rig, const std::string& name) {
  const FocusRole& role = focus_roles().at(name);
  const int joint = role.joint(rig);
  if (joint < 0)
    throw std::invalid_argument("--focus " + name + ": the model has no " + role.part +
                                " (its rig map found none), so nothing to frame");
  return joint;
}

ContactSheet::ContactSheet(SheetModel model, const SheetOptions& options, PairSource* pairs,
                           DrawCell draw)
    : model_(std::move(model)),
      options_(options),
      pairs_(pairs),
      draw_(std::move(draw)),
      meter_(model_.bound),
      heat_(model_.bound.model.positions, model_.bound.model.indices) {
  caption_scale_ = options.cell_width >= 400 ? 2 : 1;
  caption_height_ = 26 * caption_scale_;  // two lines of 12, a margin of 1 above and below
  const std::size_t vertices = model_.bound.model.vertex_count();
  positions_.resize(vertices);
  normals_.resize(vertices);
  if (options.heat) colours_.resize(vertices);
  cell_.resize(static_cast<std::size_t>(options.cell_width) *
               (options.cell_height - caption_height_) * 4);

  // The framing pass: where the body (or the joint) is at each frame, and which way it faces.
  const deform::Skeleton& skeleton = model_.bound.model.skeleton;
  const std::vector<glm::mat4> rest = skeleton.world_rest_matrices();
  const int pelvis = model_.bound.rig.torso.pelvis();
  const glm::vec3 rest_front = deform::rest_body_axes(model_.bound.rig, rest).forward;
  const int joint = options.focus.empty() ? -1 : focus_joint(model_.bound.rig, options.focus);
  const deform::MethodChoice& lbs = deform::methods_by_name().at("lbs");
  std::vector<glm::vec3> centres, towards_eye;
  const float focus_radius = kFocusRadiusPerHeight * rest_height(model_.bound.model.positions);
  glm::vec3 half_extents(focus_radius);
  if (joint < 0) half_extents = glm::vec3(0.0f);
  for (const int frame : options.frames) {
    deform_with(lbs, model_.runtime, deform_context_, nullptr, model_.pose(frame), positions_);
    const std::span<const glm::mat4> world = deform_context_.world_pose();
    const glm::vec3 eye = eye_direction(world[pelvis], rest[pelvis], rest_front,
                                        options.azimuth_degrees, options.elevation_degrees);
    towards_eye.push_back(eye);
    if (joint >= 0) {
      centres.push_back(glm::vec3(world[joint][3]));
      continue;
    }
    glm::vec3 low = positions_.front(), high = low;
    for (const glm::vec3& p : positions_) low = glm::min(low, p), high = glm::max(high, p);
    const glm::vec3 centre = 0.5f * (low + high);
    centres.push_back(centre);
    // The body's extent along this frame's view axes (right, up, towards the eye).
    const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), eye));
    const glm::mat3 axes(right, glm::cross(eye, right), eye);
    for (const glm::vec3& p : positions_)
      half_extents = glm::max(half_extents, glm::abs((p - centre) * axes));
  }
  if (joint < 0) half_extents *= kBodyMargin;
  const float aspect = static_cast<float>(options.cell_width) /
                       static_cast<float>(options.cell_height - caption_height_);
  for (std::size_t f = 0; f < centres.size(); ++f)
    cameras_.push_back(gpu::box_camera(centres[f], half_extents, towards_eye[f], aspect));
}

void ContactSheet::render_row(std::size_t frame_index, std::span<std::uint8_t> rgba, int row) {
  for (std::size_t m = 0; m < options_.methods.size(); ++m) render_cell(frame_index, m, rgba, row);
}

void ContactSheet::render_cell(std::size_t frame_index, std::size_t method,
                               std::span<std::uint8_t> rgba, int row) {
  const deform::MethodChoice& m = options_.methods[method];
  const int frame = options_.frames[frame_index];
  deform_with(m, model_.runtime, deform_context_, pairs_, model_.pose(frame), positions_);
  // Every method is shaded by its posed surface's own normals, as the sweep's are made: LBS's
  // and DQS's skinned normals keep the rest pose's smooth shading over their creases, which made
  // the sheet compare a sweep's shape with the baselines' rest shading (issue 17).
  model_.runtime.welded_normals().compute(positions_, normals_, normal_sums_);
  // Edge lengths as ratios l / l_rest, the shortest and the longest (issue 47: "stretch 297 %"
  // read as within 3x when an edge was 3.97x its rest length).
  const auto [squash, longest] = meter_.edge_ratio_range(positions_);
  edge_ratios_.push_back({squash, longest});
  if (options_.heat) heat_.colour(positions_, options_.heat_full_scale, colours_);

  const int width = options_.cell_width, render_height = options_.cell_height - caption_height_;
  gpu::PreviewOptions preview;
  preview.width = width;
  preview.height = render_height;
  preview.camera = cameras_[frame_index];
  draw_({positions_, normals_, model_.bound.model.indices, colours_}, preview, cell_);

  // Copy the caption band (white, two lines of text) and the render into the picture.
  const int picture_width = this->width();
  const int left = static_cast<int>(method) * width, top = row * options_.cell_height;
  for (int y = 0; y < caption_height_; ++y)
    std::fill_n(rgba.begin() + (static_cast<std::size_t>(top + y) * picture_width + left) * 4,
                static_cast<std::size_t>(width) * 4, std::uint8_t{255});
  for (int y = 0; y < render_height; ++y)
    std::copy_n(
        cell_.begin() + static_cast<std::size_t>(y) * width * 4,
        static_cast<std::size_t>(width) * 4,
        rgba.begin() +
            (static_cast<std::size_t>(top + caption_height_ + y) * picture_width + left) * 4);
  char detail[64];
  std::snprintf(detail, sizeof detail, "frame %d  edges %.2f-%.2fx", frame, squash, longest);
  const int height = static_cast<int>(rgba.size() / 4 / picture_width);
  // Each line is cut to the cell's width, so captions stay inside their cell.
  const std::string lines[2] = {m.name + (options_.focus.empty() ? "" : "  " + options_.focus),
                                detail};
  for (int line = 0; line < 2; ++line) {
    std::string text = lines[line];
    while (!text.empty() && text_width(text, caption_scale_) > width - 4 * caption_scale_)
      text.pop_back();
    draw_text(rgba, picture_width, height, left + 3 * caption_scale_,
              top + (1 + 12 * line) * caption_scale_, text, kCaptionInk, caption_scale_);
  }
}

SheetPicture draw_picture(ContactSheet& contact, std::string renderer) {
  SheetPicture picture;
  const int rows = static_cast<int>(contact.options().frames.size());
  picture.width = contact.width();
  picture.height = rows * contact.options().cell_height;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(picture.width) * picture.height * 4);
  for (int row = 0; row < rows; ++row) contact.render_row(row, rgba, row);
  io::encode_png(picture.width, picture.height, rgba, picture.png);
  picture.edge_ratios = contact.edge_ratios();
  picture.renderer = std::move(renderer);
  return picture;
}

}  // namespace sweepd::sheet
