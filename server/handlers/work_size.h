// Work size: the most working memory a request holds while it runs, known at intake (issue 49
// item 2), reserved from the server's WorkBudget (server/services/work_budget.h) for the work's
// life. Upper bounds from what the code allocates, so that the daemon's resident size stays
// within the budget plus its base (models, threads, libraries, the GPU driver):
//
// pose_work_bytes(request): a PosedVertices: its reply frame (largest_reply_bytes) and, for
//   Float16 and Meshopt, the float32 positions and normals deformed first (24 bytes a vertex).
// pose_work_bytes for a PositionMapRequest: per texel, the GPU's render targets (2 RGBA32F and
//   one R32F: 36 bytes; under Mesa's llvmpipe they are host memory), the read-back planes (P, N
//   when asked, A always: up to 28), the gutter's state and queues (13), half normals' scratch
//   (6 when asked); then the EXR three times (its compressed chunks, at most uncompressed; the
//   file's vector, which grows by doubling) and once more as the reply frame; and the
//   deformed vertices (24 bytes a vertex).
// sheet_work_bytes(options): a ContactSheet: the picture's RGBA (4 bytes a pixel), stb's
//   filtered rows (4), the PNG four times at worst (its zlib buffer growing by doubling, stb's
//   copy, ours) and the reply frame; per cell, the preview renderer's 4x multisampled colour
//   and depth and the resolved colour (36 bytes a cell pixel) and the cell's read-back (4).
// clip_upload_work_bytes(upload_bytes): an UploadClip while it is read: 4 bytes for each
//   uploaded byte (a BVH number is at least 2 characters and becomes a 4-byte float, read
//   into channels and then rotations). An estimate, not a bound, for a glTF animation whose
//   sparse keys are sampled at many frames: the held clip counts against --max-clip-bytes by
//   its uploaded bytes.
// model_upload_work_bytes(upload_bytes): a LoadModel's copy of its upload, taken off the frame
//   at intake and held for the load's life (loads bind one at a time: it waits with them).
// model_reading_work_bytes(file_bytes): reading the model file once the load's turn comes: 5
//   bytes a byte of it (the file read back, tinygltf's or assimp's buffers, the Model; sweepctl
//   inspect's peak over its base was 4.6 times the .glb of the 80k and 300k mannequins).
// model_binding_work_bytes(model): binding the model read, its self-check on the range of
//   motion, its adaptation and the store's .sweepbind encoding: 900 bytes a vertex and 256 a
//   triangle (sweepctl bind's peak over its base, the reading included, was 1,280-1,360 bytes
//   a vertex on the 20k, 80k and 300k mannequins, 1.95 triangles a vertex; the split between
//   vertices and triangles is not measured apart). The reading's buffers are freed before it
//   binds: its reservation counts toward the binding (model_binding_extra_bytes).
//   Estimates, as the clip's: measured on glTF bodies.
// model_adoption_work_bytes(binding_bytes): adopting a model another replica stored (LoadModel
//   by content id, by name, or an upload whose content id the store holds): 10 bytes a byte of
//   its .sweepbind — the bytes read, the binding decoded, its runtime and, when its self-check's
//   sidecar is missing or stale, the self-check run again (sweepd's peak over its base while
//   reading one stored mannequin: 8.5 bytes a byte at 80k vertices, 9.1 at 20k; 4.8 and 5.1
//   with the sidecar).
// key_ellipse_edit_work_bytes(binding_bytes): an EditKeyEllipse, sized by the held binding's
//   .sweepbind: the copy edited (or the store's version read again, as an adoption reads it:
//   another replica edited it), its runtime, its self-check run again and the edited binding
//   encoded for the store: 12 bytes a byte (the adoption's 10 and the encoding; an edit of a
//   20k mannequin's 3.6 MB binding peaked 27 MB over the daemon's resident size: 7.5).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "deform/model/model.h"
#include "server/handlers/pose_request.h"
#include "server/handlers/request_error.h"
#include "server/services/contact_sheet_service.h"
#include "server/services/work_budget.h"

namespace sweepd::server {

std::uint64_t pose_work_bytes(const PoseRequest& request);

std::uint64_t sheet_work_bytes(const sheet::SheetOptions& options);

std::uint64_t clip_upload_work_bytes(std::uint64_t upload_bytes);

std::uint64_t model_upload_work_bytes(std::uint64_t upload_bytes);

std::uint64_t model_reading_work_bytes(std::uint64_t file_bytes);

std::uint64_t model_binding_work_bytes(const deform::Model& model);

std::uint64_t model_adoption_work_bytes(std::uint64_t binding_bytes);

std::uint64_t key_ellipse_edit_work_bytes(std::uint64_t binding_bytes);

// What binding `model` needs beyond its reading's reservation (of `file_bytes`).
std::uint64_t model_binding_extra_bytes(const deform::Model& model, std::uint64_t file_bytes);

// request.work set to a reservation of pose_work_bytes from `budget` for `client`, or the
// ResourceExhausted to answer: its bytes, the limit it passed and what to ask for instead.
std::optional<RequestError> reserve_pose_work(PoseRequest& request, WorkBudget& budget,
                                              std::uint64_t client);

// "needs 1,234 bytes of working memory, over what the server's work budget has free now
// (--work-budget-bytes 5,678, 5,000 held by all clients: 678 fit)", or the same of the client's
// share (--work-budget-client-bytes).
std::string describe(const WorkRefusal& refusal);

// The ResourceExhausted for any refused request: "<what>: <describe>; <smaller>, or retry when
// this server's other work has finished".
RequestError work_refused(const std::string& what, const WorkRefusal& refusal,
                          const std::string& smaller);

}  // namespace sweepd::server
