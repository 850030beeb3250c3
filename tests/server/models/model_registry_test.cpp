// ModelRegistry without a daemon: the store's restore after damage (corrupt and truncated files
// quarantined, crashed writers' temporaries removed, live ones kept), a store of the first
// layout migrated to content ids, two registries sharing one store (as replicas on a shared
// volume: a model stored by one is adopted by the other; concurrent writers never tear a file),
// a StoreSlot keeping a second load out until the first is stored, and concurrent edits of one
// model all kept — by threads of one registry and by two registries on one store, each of
// which serves the other's edits from its next current() and never loads a damaged file.
#include "server/models/model_registry.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/files/durable_file.h"
#include "io/sweepbind/sweepbind.h"
#include "mannequin/mannequin.h"
#include "selfcheck/binding_self_check.h"
#include "server/models/content_id.h"
#include "server/models/self_check_sidecar.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test::model_registry_test {
namespace {

namespace fs = std::filesystem;

const deform::BoundModel& small_bound_mannequin() {
  static const deform::BoundModel bound = [] {
    const deform::Model model = mannequin::make_mannequin({.target_vertices = 2000});
    return deform::bind(model, deform::detect_rig_map(model.skeleton));
  }();
  return bound;
}

// Its self-check, as a load gives it to add().
const server::SelfCheck& small_mannequin_check() {
  static const server::SelfCheck checked = server::self_check(small_bound_mannequin());
  return checked;
}

// Test models' content ids: any 64 hex digits name a model to the registry.
std::string id_for(const std::string& name) { return server::described_content_id(name); }

server::ModelHandle add(server::ModelRegistry& registry, const std::string& name) {
  return registry.add(registry.claim(name, id_for(name)), name, small_bound_mannequin(), 1,
                      small_mannequin_check());
}

fs::path stored(const fs::path& directory, const std::string& name, const char* suffix) {
  return directory / (id_for(name) + suffix);
}

void write_bytes(const fs::path& file, std::span<const std::uint8_t> bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::string> names(const server::ModelRegistry& registry) {
  std::vector<std::string> out;
  for (const server::ModelHandle& model : registry.models()) out.push_back(model->name);
  return out;
}

const server::StoreProblem* problem_with(const server::RestoreReport& report,
                                         const fs::path& file) {
  for (const server::StoreProblem& problem : report.problems)
    if (problem.file == file) return &problem;
  return nullptr;
}

// Damage of every kind at once: a flipped byte (checksum), a truncated file, and the
// temporaries a kill leaves. Each damaged model is moved aside whole with its sources, every
// other model loads; temporaries of writers that are gone are removed, a live writer's kept.
TEST(ModelRegistry, RestoreQuarantinesDamagedFilesAndLoadsEveryOtherModel) {
  const fs::path directory = fresh_directory("registry");
  {
    server::ModelRegistry registry(directory, 16);
    for (const char* name : {"flipped", "good", "truncated", "also_good"}) add(registry, name);
  }
  const fs::path flipped_file = stored(directory, "flipped", ".sweepbind");
  std::vector<std::uint8_t> flipped = read_bytes(flipped_file);
  flipped[100] ^= 0x7f;  // one payload byte: the checksum fails
  write_bytes(flipped_file, flipped);
  write_bytes(stored(directory, "flipped", ".glb"), std::vector<std::uint8_t>{'g', 'l', 'T', 'F'});
  const fs::path truncated_file = stored(directory, "truncated", ".sweepbind");
  std::vector<std::uint8_t> truncated = read_bytes(truncated_file);
  truncated.resize(truncated.size() / 2);
  write_bytes(truncated_file, truncated);
  // What kills leave mid-write, by writer: an older sweepd (no writer in the name), a process of
  // this host that no longer runs (pid 999999999 exceeds any pid_max), another host's an hour
  // ago: removed. A live process of this host (our parent) and another host's just now: kept,
  // they may still rename.
  const std::string host = io::this_host();
  const std::vector<std::uint8_t> torn(64, 0);
  const fs::path legacy = directory / "index.json.tmp",
                 dead = directory / ("x.sweepbind.999999999@" + host + ".tmp"),
                 old_remote = directory / "y.sweepbind.7@elsewhere.tmp",
                 live =
                     directory / ("z.sweepbind." + std::to_string(getppid()) + "@" + host + ".tmp"),
                 fresh_remote = directory / "w.sweepbind.7@elsewhere.tmp";
  for (const fs::path& file : {legacy, dead, old_remote, live, fresh_remote})
    write_bytes(file, torn);
  fs::last_write_time(old_remote, fs::file_time_type::clock::now() - std::chrono::hours(2));

  server::ModelRegistry registry(directory, 16);
  const server::RestoreReport report = registry.restore();
  std::vector<std::string> restored = names(registry);
  std::sort(restored.begin(), restored.end());
  EXPECT_EQ(restored, (std::vector<std::string>{"also_good", "good"}));
  EXPECT_EQ(report.migrated, 0u);
  ASSERT_EQ(report.problems.size(), 2u);
  const server::StoreProblem* checksum = problem_with(report, flipped_file);
  const server::StoreProblem* cut = problem_with(report, truncated_file);
  ASSERT_TRUE(checksum && cut);
  EXPECT_NE(checksum->reason.find("checksum"), std::string::npos) << checksum->reason;
  EXPECT_NE(cut->reason.find("truncated"), std::string::npos) << cut->reason;
  // Moved aside byte for byte, never deleted; the damaged model's sources go with it.
  EXPECT_EQ(checksum->quarantined_to.parent_path(), directory / "quarantine");
  EXPECT_TRUE(
      checksum->quarantined_to.filename().string().starts_with(flipped_file.filename().string()));
  EXPECT_EQ(read_bytes(checksum->quarantined_to), flipped);
  EXPECT_EQ(read_bytes(cut->quarantined_to), truncated);
  for (const char* suffix : {".sweepbind", ".glb", ".json", server::kSelfCheckSuffix})
    EXPECT_FALSE(fs::exists(stored(directory, "flipped", suffix))) << suffix;
  EXPECT_FALSE(fs::exists(truncated_file));
  std::size_t quarantined_sources = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory / "quarantine"))
    quarantined_sources += entry.path().filename().string().starts_with(id_for("flipped") + ".");
  EXPECT_EQ(quarantined_sources, 4u) << ".sweepbind, .glb, .json and .selfcheck.json";
  EXPECT_EQ(report.removed_temporaries.size(), 3u);
  for (const fs::path& file : {legacy, dead, old_remote}) EXPECT_FALSE(fs::exists(file)) << file;
  for (const fs::path& file : {live, fresh_remote}) EXPECT_TRUE(fs::exists(file)) << file;
  // A model stored again under a damaged one's id is a new model, found at the next start.
  EXPECT_EQ(add(registry, "flipped")->id, server::handle_of(id_for("flipped")));
  server::ModelRegistry again(directory, 16);
  EXPECT_TRUE(again.restore().problems.empty());
  EXPECT_EQ(again.models().size(), 3u);
  fs::remove_all(directory);
}

// A store of the first layout (index.json, <n>.sweepbind, <n>.glb) moves to content ids: every
// model keeps its name and binding, its source moves with it, the index goes; the next start
// finds the new layout and the same handles.
TEST(ModelRegistry, AStoreOfTheFirstLayoutIsMigratedToContentIds) {
  const fs::path directory = fresh_directory("registry_migration");
  deform::BoundModel named = small_bound_mannequin();
  for (const auto& [id, name] : {std::pair{1, "first"}, std::pair{2, "second"}}) {
    named.model.name = name;
    io::save_sweepbind(named, directory / (std::to_string(id) + ".sweepbind"));
  }
  write_bytes(directory / "1.glb", std::vector<std::uint8_t>{'g', 'l', 'T', 'F'});
  std::ofstream(directory / "index.json")
      << R"({"version":1,"next_id":3,"models":[{"id":1,"name":"first","file":"1.sweepbind",)"
      << R"("bind_time_ns":5},{"id":2,"name":"renamed","file":"2.sweepbind","bind_time_ns":6}]})";
  std::map<std::string, std::uint32_t> handles;
  {
    server::ModelRegistry registry(directory, 16);
    const server::RestoreReport report = registry.restore();
    EXPECT_TRUE(report.problems.empty());
    EXPECT_EQ(report.migrated, 2u);
    for (const server::ModelHandle& model : registry.models()) {
      handles[model->name] = model->id;
      EXPECT_TRUE(server::is_content_id(model->content_id)) << model->content_id;
      EXPECT_EQ(model->bound.model.vertex_count(), named.model.vertex_count());
      EXPECT_TRUE(fs::exists(directory / (model->content_id + ".sweepbind")));
    }
    EXPECT_EQ(handles.size(), 2u);
    EXPECT_TRUE(handles.contains("renamed")) << "the index's name, not the binding's";
    EXPECT_TRUE(
        fs::exists(directory / (registry.find(std::string_view("first"))->content_id + ".glb")));
  }
  for (const char* gone : {"index.json", "1.sweepbind", "2.sweepbind", "1.glb"})
    EXPECT_FALSE(fs::exists(directory / gone)) << gone;
  server::ModelRegistry again(directory, 16);
  const server::RestoreReport clean = again.restore();
  EXPECT_TRUE(clean.problems.empty());
  EXPECT_EQ(clean.migrated, 0u);
  for (const auto& [name, handle] : handles)
    EXPECT_EQ(again.find(std::string_view(name))->id, handle) << name;
  fs::remove_all(directory);
}

// Two replicas on one store: a model the first stores after the second started is adopted by
// the second — same handle, same binding — and found by its name; a model whose name the
// second already holds under another content id is left in the store, reported, not moved.
TEST(ModelRegistry, ReplicasSharingAStoreAdoptEachOthersModels) {
  const fs::path directory = fresh_directory("registry_shared");
  server::ModelRegistry first(directory, 16), second(directory, 16);
  first.restore();
  second.restore();
  const server::ModelHandle stored_by_first = add(first, "hero");
  EXPECT_EQ(second.find_content(id_for("hero")), nullptr);
  EXPECT_EQ(second.stored_content_named("hero"), id_for("hero"));
  const server::ModelHandle adopted = second.adopt(id_for("hero"));
  ASSERT_NE(adopted, nullptr);
  EXPECT_EQ(adopted->id, stored_by_first->id);
  EXPECT_EQ(adopted->name, "hero");
  EXPECT_EQ(adopted->bound.model.positions, stored_by_first->bound.model.positions);
  EXPECT_EQ(second.adopt(id_for("nobody")), nullptr) << "not in the store";

  // "villain" under two content ids, one per replica: each keeps its own, neither is moved.
  second.add(second.claim("villain", id_for("villain 2")), "villain", small_bound_mannequin(), 1,
             small_mannequin_check());
  first.add(first.claim("villain", id_for("villain 1")), "villain", small_bound_mannequin(), 1,
            small_mannequin_check());
  server::ModelRegistry third(directory, 16);
  const server::RestoreReport report = third.restore();
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_NE(report.problems[0].reason.find("a model named 'villain' is loaded"), std::string::npos)
      << report.problems[0].reason;
  EXPECT_TRUE(report.problems[0].quarantined_to.empty());
  EXPECT_TRUE(fs::exists(report.problems[0].file));
  fs::remove_all(directory);
}

// Two processes (replicas) store the same model over and over while this one reads it: every
// read loads a whole, checksum-valid binding — each writer renames its own temporary.
TEST(ModelRegistry, ConcurrentWritersOfOneModelNeverTearIt) {
  const fs::path directory = fresh_directory("registry_writers");
  {
    server::ModelRegistry seed(directory, 16);
    add(seed, "shared");
  }
  const fs::path file = stored(directory, "shared", ".sweepbind");
  std::vector<pid_t> writers;
  for (int w = 0; w < 2; ++w) {
    const pid_t pid = fork();
    if (pid == 0) {
      for (int i = 0; i < 20; ++i) io::save_sweepbind(small_bound_mannequin(), file);
      _exit(0);
    }
    writers.push_back(pid);
  }
  int reads = 0, running = 2;
  while (running > 0) {
    EXPECT_NO_THROW(io::load_sweepbind(file));
    ++reads;
    running = 0;
    for (pid_t pid : writers) running += waitpid(pid, nullptr, WNOHANG) == 0;
  }
  for (pid_t pid : writers) waitpid(pid, nullptr, 0);
  EXPECT_GE(reads, 1);
  std::size_t left = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory))
    left += entry.path().extension() == ".tmp";
  EXPECT_EQ(left, 0u) << "every writer renamed its temporary";
  fs::remove_all(directory);
}

TEST(ModelRegistry, AClaimIsRefusedWhenFullOrTheNameIsTaken) {
  const fs::path directory = fresh_directory("registry_claims");
  server::ModelRegistry registry(directory, 2);
  add(registry, "first");
  try {
    registry.claim("first", id_for("another first"));
    FAIL() << "a second model called 'first' was claimed";
  } catch (const server::ModelError& error) {
    EXPECT_EQ(error.code(), protocol::ErrorCode::ModelLoadFailed);
    EXPECT_NE(std::string(error.what()).find(id_for("first")), std::string::npos) << error.what();
  }
  add(registry, "second");
  try {
    registry.claim("third", id_for("third"));
    FAIL() << "a third model was claimed past the limit of 2";
  } catch (const server::ModelError& error) {
    EXPECT_EQ(error.code(), protocol::ErrorCode::ModelLimit);
  }
  fs::remove_all(directory);
}

TEST(ModelRegistry, ASlotKeepsTheNextLoadOutUntilItsModelIsStored) {
  const fs::path directory = fresh_directory("registry_slots");
  server::ModelRegistry registry(directory, 16);
  server::ModelRegistry::StoreSlot first = registry.claim("first", id_for("first"));
  EXPECT_EQ(first.id(), server::handle_of(id_for("first")));
  EXPECT_EQ(first.file(".glb"), stored(directory, "first", ".glb"));
  std::atomic<bool> second_claimed = false;
  std::thread second([&] {
    server::ModelRegistry::StoreSlot slot = registry.claim("second", id_for("second"));
    second_claimed = true;
    registry.add(std::move(slot), "second", small_bound_mannequin(), 1, small_mannequin_check());
  });
  // Lookups go on while a slot is held; the second claim waits. 100 ms is ample for an unblocked
  // thread to claim (it only checks a list); a slow machine could only hide a broken lock from
  // this check, never fail a working one.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(second_claimed);
  EXPECT_TRUE(registry.models().empty());
  registry.add(std::move(first), "first", small_bound_mannequin(), 1, small_mannequin_check());
  second.join();
  ASSERT_EQ(registry.models().size(), 2u);
  EXPECT_TRUE(fs::exists(stored(directory, "second", ".sweepbind")));
  fs::remove_all(directory);
}

// Two threads edit different keys of one model at once: every edit is in the stored model (an
// edit that copied the binding before another was swapped in would drop that one).
// Two threads edit model `id` at once, thread t through editors[t], `edits` times each: edit k
// sets sweep t's key k (mod the key count) to a = 0.01 (k + 1) + t / 1000, each value distinct.
// Then every last edit of each thread (one per key) is in the stored binding and in what each
// editor's current() serves — exactly: the value is set as a float and stored bit for bit. An
// edit that started from a copy older than another's would drop that one.
void expect_concurrent_edits_kept(const fs::path& directory,
                                  std::array<server::ModelRegistry*, 2> editors, std::uint32_t id,
                                  int edits) {
  const auto value = [](int t, int k) { return 0.01f * static_cast<float>(k + 1) + 0.001f * t; };
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < edits; ++k) {
        editors[t]->replace(id, [&](deform::BoundModel& bound) {
          auto& keys = bound.sweeps[t].rest_keys;
          keys[k % keys.size()].a = value(t, k);
        });
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  const deform::BoundModel stored_model =
      io::load_sweepbind(stored(directory, "edited", ".sweepbind"));
  for (int t = 0; t < 2; ++t) {
    const std::size_t keys = stored_model.sweeps[t].rest_keys.size();
    for (int k = edits - static_cast<int>(std::min<std::size_t>(keys, edits)); k < edits; ++k) {
      EXPECT_EQ(stored_model.sweeps[t].rest_keys[k % keys].a, value(t, k))
          << "sweep " << t << " edit " << k;
      for (server::ModelRegistry* editor : editors)
        EXPECT_EQ(editor->current(id)->bound.sweeps[t].rest_keys[k % keys].a, value(t, k));
    }
  }
}

TEST(ModelRegistry, ConcurrentEditsOfOneModelAreAllKept) {
  const fs::path directory = fresh_directory("registry_edits");
  server::ModelRegistry registry(directory, 16);
  const std::uint32_t id = add(registry, "edited")->id;
  ASSERT_GE(small_bound_mannequin().sweeps.size(), 2u);
  expect_concurrent_edits_kept(directory, {&registry, &registry}, id, 12);
  fs::remove_all(directory);
}

// Two replicas on one store edit one model at once, each its own sweep: every edit of both is
// in the store, and each replica's current() serves it — without a restart, reading the file
// once per change. A held model is brought up to date only by current(); find() answers from
// memory.
TEST(ModelRegistry, ReplicasSharingAStoreServeAndKeepEachOthersEdits) {
  const fs::path directory = fresh_directory("registry_shared_edits");
  server::ModelRegistry first(directory, 16), second(directory, 16);
  const std::uint32_t id = add(first, "edited")->id;
  ASSERT_NE(second.adopt(id_for("edited")), nullptr);
  const float original = second.find(id)->bound.sweeps[0].rest_keys[0].a;

  first.replace(id, [](deform::BoundModel& bound) { bound.sweeps[0].rest_keys[0].a = 0.123f; });
  EXPECT_EQ(second.find(id)->bound.sweeps[0].rest_keys[0].a, original) << "find: as held";
  const server::ModelHandle reloaded = second.current(id);
  EXPECT_EQ(reloaded->bound.sweeps[0].rest_keys[0].a, 0.123f);  // stored bit for bit
  EXPECT_EQ(second.current(id), reloaded) << "read once per change";
  EXPECT_EQ(first.current(id), first.find(id)) << "its own edit is not read back";

  expect_concurrent_edits_kept(directory, {&first, &second}, id, 8);

  // A damaged file renamed over the binding (as no sweepd writes one) is never loaded: it is
  // quarantined, and the copy held serves on.
  const fs::path file = stored(directory, "edited", ".sweepbind");
  std::vector<std::uint8_t> damaged = read_bytes(file);
  damaged[100] ^= 0x7f;
  io::write_file_durably(file, damaged);
  const server::ModelHandle held = second.find(id);
  std::optional<server::StoreProblem> problem;
  EXPECT_EQ(second.current(id, &problem), held);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->reason.find("checksum"), std::string::npos) << problem->reason;
  EXPECT_EQ(problem->quarantined_to.parent_path(), directory / "quarantine");
  EXPECT_EQ(read_bytes(problem->quarantined_to), damaged);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_EQ(second.current(id), held) << "nothing in the store: the held copy";
  fs::remove_all(directory);
}

// A self-check no binding of the small mannequin gives (the check finds it loses nowhere, or
// not so): 7 poses and a warning whose figures need every digit of a double. A model that
// shows it after a restore read it from the store; one that checked itself again shows
// small_mannequin_check() instead.
server::SelfCheck doctored_check() {
  return {.poses = 7,
          .warnings = {{.region = "left arm",
                        .worse_poses = 3,
                        .pose_count = 7,
                        .sweep = 1.2345678901234567,
                        .baseline = 1.0000000000000002,
                        .baseline_name = "DQS",
                        .pose = "elbow flexion 150°",
                        .extra_flipped = 2,
                        .flipped_pose = "shoulder abduction",
                        .text = "left arm: as stored"}}};
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// Restores, adoptions and reloads read the verdicts stored with the binding (issue 47): the
// check of 48 poses is not run again at every start.
TEST(ModelRegistry, ARestoreReadsTheStoredSelfCheckInsteadOfCheckingAgain) {
  const fs::path directory = fresh_directory("registry_self_check");
  ASSERT_NE(doctored_check(), small_mannequin_check()) << "the test could not tell them apart";
  {
    server::ModelRegistry registry(directory, 16);
    registry.add(registry.claim("checked", id_for("checked")), "checked", small_bound_mannequin(),
                 1, doctored_check());
  }
  server::ModelRegistry restored(directory, 16);
  EXPECT_TRUE(restored.restore().problems.empty());
  const server::ModelHandle model = restored.find_content(id_for("checked"));
  ASSERT_NE(model, nullptr);
  // Field for field, doubles bit for bit (SelfCheck's operator== compares every field).
  EXPECT_EQ(model->self_check, doctored_check());

  server::ModelRegistry replica(directory, 16);
  const server::ModelHandle adopted = replica.adopt(id_for("checked"));
  ASSERT_NE(adopted, nullptr);
  EXPECT_EQ(adopted->self_check, doctored_check()) << "an adoption reads it too";
  fs::remove_all(directory);
}

// A sidecar that is not the binding's — another binding's checksum, an older self-check's
// revision, torn, absent — is not read: the binding is checked again, and the sidecar written
// anew with its key.
TEST(ModelRegistry, AStoredSelfCheckOfAnotherBindingOrRevisionIsCheckedAgain) {
  const fs::path directory = fresh_directory("registry_stale_self_check");
  {
    server::ModelRegistry registry(directory, 16);
    registry.add(registry.claim("checked", id_for("checked")), "checked", small_bound_mannequin(),
                 1, doctored_check());
  }
  const fs::path sidecar = stored(directory, "checked", server::kSelfCheckSuffix);
  const nlohmann::json good = read_json(sidecar);
  const io::SweepbindChecksum binding =
      io::sweepbind_checksum(read_bytes(stored(directory, "checked", ".sweepbind")));
  EXPECT_EQ(good["binding"]["crc32"], binding.crc32);
  EXPECT_EQ(good["binding"]["payload_size"], binding.payload_size);

  nlohmann::json other_binding = good, older_check = good;
  other_binding["binding"]["crc32"] = binding.crc32 ^ 1u;
  older_check["self_check_revision"] = selfcheck::kSelfCheckRevision - 1;
  const std::string torn = good.dump().substr(0, 40);
  for (const std::string& stale :
       {other_binding.dump(), older_check.dump(), torn, std::string("absent")}) {
    if (stale == "absent") {
      fs::remove(sidecar);
    } else {
      write_bytes(sidecar,
                  std::span(reinterpret_cast<const std::uint8_t*>(stale.data()), stale.size()));
    }
    server::ModelRegistry restored(directory, 16);
    restored.restore();
    const server::ModelHandle model = restored.find_content(id_for("checked"));
    ASSERT_NE(model, nullptr) << stale;
    EXPECT_EQ(model->self_check, small_mannequin_check()) << stale;
    const nlohmann::json rewritten = read_json(sidecar);
    EXPECT_EQ(rewritten["binding"], good["binding"]) << stale;
    EXPECT_EQ(rewritten["self_check_revision"], selfcheck::kSelfCheckRevision) << stale;
    EXPECT_EQ(rewritten["poses"], small_mannequin_check().poses) << stale;
  }
  fs::remove_all(directory);
}

// An edit changes what the sweep does: it checks the edited binding again and stores that.
TEST(ModelRegistry, AnEditChecksTheBindingAgainAndStoresItsVerdicts) {
  const fs::path directory = fresh_directory("registry_edit_self_check");
  server::ModelRegistry registry(directory, 16);
  const std::uint32_t id = registry
                               .add(registry.claim("checked", id_for("checked")), "checked",
                                    small_bound_mannequin(), 1, doctored_check())
                               ->id;
  // A key made 3 times wider: the check's figures change with it.
  const server::ModelHandle edited = registry.replace(
      id, [](deform::BoundModel& bound) { bound.sweeps[0].rest_keys[0].a *= 3.0f; });
  EXPECT_EQ(edited->self_check, server::self_check(edited->bound));
  EXPECT_NE(edited->self_check, doctored_check());
  server::ModelRegistry restored(directory, 16);
  restored.restore();
  EXPECT_EQ(restored.find(id)->self_check, edited->self_check) << "the edit's verdicts stored";
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test::model_registry_test
