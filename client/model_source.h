// ModelSource: how a client names its model to every server it talks to — several servers,
// reconnects behind HAProxy, replicas with or without a shared store — sending the model's
// bytes only to a server that lacks them (issue 14 item 2).
//
// The first load() is the client's request as given: an upload (name + .glb bytes, and a rig
// map and orientation curve if any) or a name the server knows (its default model, a model
// directory file). The ModelInfo answering it carries the model's content id (protocol 1.3). Every
// later load(), on any connection, asks for that content id first (LoadModel{content_id}, no bytes:
// the server holds the model, or adopts it from a store it shares with the replica that bound it);
// only a server that answers UnknownModel gets the request as given again — the upload, once, on
// that connection. A server older than 1.3 ignores content_id and answers the name as before.
//
//   ModelSource source("body.glb", bytes);             // or ModelSource("mannequin", {})
//   const protocol::ModelInfo& info = source.load(connection);   // on each new connection
//
// A client that gets UnknownModel (or loses its connection: client/reconnect.h) for a request
// naming the model calls load() again — on the same connection or a new one — and asks again,
// once: stream_poses, render_frames and `sweepctl --server` do.
//
// model_name_of_file(path): the name a client uploads a model file under unless its user gives
// one — the file's base name, without its folder and extension ("/home/me/body.glb" ->
// "body"), the name the server holds it by (issue 48: one name per model, never a client's
// local path; the server cuts a path it is sent to the same). Clients print the name the
// ModelInfo answering them carries: a server that held the same bytes already keeps its name.
//
// uploads(): how many times the bytes were sent (1 in a fleet sharing a store). Thread-safe:
// render_frames' server threads share one. Throws what Connection throws (ServerError with
// the server's code, std::runtime_error).
#pragma once

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "client/connection.h"

namespace sweepd::client {

std::string model_name_of_file(const std::filesystem::path& file);

class ModelSource {
 public:
  // orientation: BindOptions.orientation (0 the paper's linear curve, 1 the smooth one).
  ModelSource(std::string name, std::vector<std::uint8_t> glb, std::string rig_map_json = {},
              std::uint8_t orientation = 0);

  const protocol::ModelInfo& load(Connection& connection);
  int uploads() const;
  const std::string& name() const { return name_; }

 private:
  // LoadModel{name, bytes, rig map, content id}; an empty content id asks as given.
  const protocol::ModelInfo& request(Connection& connection, const std::string& content_id,
                                     bool with_bytes);
  // Keeps the content id of the first answer.
  void remember(const protocol::ModelInfo& info);

  const std::string name_, rig_map_json_;
  const std::vector<std::uint8_t> glb_;
  const std::uint8_t orientation_;
  mutable std::mutex mutex_;
  std::string content_id_;  // from the first ModelInfo; empty before it, or from an old server
  int uploads_ = 0;
};

}  // namespace sweepd::client
