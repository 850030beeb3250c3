// ModelRegistry without a process: the store's restore after damage (corrupt, truncated and
// missing files quarantined or dropped, crash temporaries removed, an unreadable index rebuilt),
// ids never reused, a StoreSlot keeping a second load out until the first is stored, and
// concurrent edits of one model all kept.
#include "server/models/model_registry.h"

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <thread>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/sweepbind.h"
#include "mannequin/mannequin.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {
namespace {

namespace fs = std::filesystem;

const deform::BoundModel& small_bound_mannequin() {
  static const deform::BoundModel bound = [] {
    const deform::Model model = mannequin::make_mannequin({.target_vertices = 2000});
    return deform::bind(model, deform::detect_rig_map(model.skeleton));
  }();
  return bound;
}

server::ModelHandle add(server::ModelRegistry& registry, const std::string& name) {
  return registry.add(registry.claim(name), name, small_bound_mannequin(), 1);
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

// Damage of every kind at once: a flipped byte (checksum), a truncated file, an index entry
// whose file is gone, and the temporaries a kill leaves. Each damaged file is moved aside
// whole, every other model loads, and ids are never reused.
TEST(ModelRegistry, RestoreQuarantinesDamagedFilesAndLoadsEveryOtherModel) {
  const fs::path directory = fresh_directory("registry");
  {
    server::ModelRegistry registry(directory, 16);
    for (const char* name : {"flipped", "good", "truncated", "missing", "also_good"})
      add(registry, name);
  }
  std::vector<std::uint8_t> flipped = read_bytes(directory / "1.sweepbind");
  flipped[100] ^= 0x7f;  // one payload byte: the checksum fails
  write_bytes(directory / "1.sweepbind", flipped);
  write_bytes(directory / "1.glb", std::vector<std::uint8_t>{'g', 'l', 'T', 'F'});  // its source
  std::vector<std::uint8_t> truncated = read_bytes(directory / "3.sweepbind");
  truncated.resize(truncated.size() / 2);
  write_bytes(directory / "3.sweepbind", truncated);
  fs::remove(directory / "4.sweepbind");
  // What a kill leaves mid-write: never loaded, removed.
  write_bytes(directory / "index.json.tmp", std::vector<std::uint8_t>{'{'});
  write_bytes(directory / "6.sweepbind.tmp", std::vector<std::uint8_t>(64, 0));

  server::ModelRegistry registry(directory, 16);
  const server::RestoreReport report = registry.restore();
  EXPECT_EQ(names(registry), (std::vector<std::string>{"good", "also_good"}));
  EXPECT_FALSE(report.index_rebuilt);
  ASSERT_EQ(report.problems.size(), 3u);
  const server::StoreProblem* checksum = problem_with(report, directory / "1.sweepbind");
  const server::StoreProblem* cut = problem_with(report, directory / "3.sweepbind");
  const server::StoreProblem* missing = problem_with(report, directory / "4.sweepbind");
  ASSERT_TRUE(checksum && cut && missing);
  EXPECT_NE(checksum->reason.find("checksum"), std::string::npos) << checksum->reason;
  EXPECT_NE(cut->reason.find("truncated"), std::string::npos) << cut->reason;
  EXPECT_NE(missing->reason.find("missing"), std::string::npos) << missing->reason;
  EXPECT_TRUE(missing->quarantined_to.empty());
  // Moved aside byte for byte, never deleted; the damaged model's source goes with it.
  EXPECT_EQ(checksum->quarantined_to.parent_path(), directory / "quarantine");
  EXPECT_TRUE(checksum->quarantined_to.filename().string().starts_with("1.sweepbind."));
  EXPECT_EQ(read_bytes(checksum->quarantined_to), flipped);
  EXPECT_EQ(read_bytes(cut->quarantined_to), truncated);
  EXPECT_FALSE(fs::exists(directory / "1.sweepbind"));
  EXPECT_FALSE(fs::exists(directory / "1.glb"));
  EXPECT_FALSE(fs::exists(directory / "3.sweepbind"));
  std::size_t quarantined_glb = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory / "quarantine"))
    quarantined_glb += entry.path().filename().string().starts_with("1.glb.");
  EXPECT_EQ(quarantined_glb, 1u);
  EXPECT_EQ(report.removed_temporaries.size(), 2u);
  EXPECT_FALSE(fs::exists(directory / "index.json.tmp"));
  EXPECT_FALSE(fs::exists(directory / "6.sweepbind.tmp"));
  // New ids never reuse an old one, even a dropped one.
  EXPECT_EQ(add(registry, "third")->id, 6u);
  EXPECT_EQ(registry.find(std::string_view("third"))->id, 6u);

  // The index was rewritten without the dropped entries: the next start finds nothing wrong.
  server::ModelRegistry again(directory, 16);
  EXPECT_TRUE(again.restore().problems.empty());
  EXPECT_EQ(names(again), (std::vector<std::string>{"good", "also_good", "third"}));
  fs::remove_all(directory);
}

// An unreadable index is quarantined and rebuilt from the .sweepbind files, which hold their
// models' names; a new model then takes a fresh id instead of overwriting a file.
TEST(ModelRegistry, AnUnreadableIndexIsQuarantinedAndRebuiltFromTheFiles) {
  const fs::path directory = fresh_directory("registry_index");
  {
    server::ModelRegistry registry(directory, 16);
    deform::BoundModel named = small_bound_mannequin();
    for (const char* name : {"first", "second"}) {
      named.model.name = name;  // as ModelService::load names the model it binds
      registry.add(registry.claim(name), name, named, 1);
    }
  }
  const std::string torn = read_text(directory / "index.json").substr(0, 40);
  write_bytes(directory / "index.json",
              std::span(reinterpret_cast<const std::uint8_t*>(torn.data()), torn.size()));
  server::ModelRegistry registry(directory, 16);
  const server::RestoreReport report = registry.restore();
  EXPECT_TRUE(report.index_rebuilt);
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_NE(report.problems[0].reason.find("unreadable index"), std::string::npos);
  EXPECT_EQ(read_text(report.problems[0].quarantined_to), torn);
  EXPECT_EQ(names(registry), (std::vector<std::string>{"first", "second"}));
  EXPECT_EQ(add(registry, "third")->id, 3u);
  server::ModelRegistry again(directory, 16);
  const server::RestoreReport clean = again.restore();
  EXPECT_TRUE(clean.problems.empty());
  EXPECT_FALSE(clean.index_rebuilt);
  EXPECT_EQ(names(again), (std::vector<std::string>{"first", "second", "third"}));
  fs::remove_all(directory);
}

TEST(ModelRegistry, AClaimIsRefusedWhenFullOrTheNameIsTaken) {
  const fs::path directory = fresh_directory("registry_claims");
  server::ModelRegistry registry(directory, 2);
  add(registry, "first");
  try {
    registry.claim("first");
    FAIL() << "a second model called 'first' was claimed";
  } catch (const server::ModelError& error) {
    EXPECT_EQ(error.code(), protocol::ErrorCode::ModelLoadFailed);
    EXPECT_NE(std::string(error.what()).find("id 1"), std::string::npos) << error.what();
  }
  add(registry, "second");
  try {
    registry.claim("third");
    FAIL() << "a third model was claimed past the limit of 2";
  } catch (const server::ModelError& error) {
    EXPECT_EQ(error.code(), protocol::ErrorCode::ModelLimit);
  }
  fs::remove_all(directory);
}

TEST(ModelRegistry, ASlotKeepsTheNextLoadOutUntilItsModelIsStored) {
  const fs::path directory = fresh_directory("registry_slots");
  server::ModelRegistry registry(directory, 16);
  server::ModelRegistry::StoreSlot first = registry.claim("first");
  EXPECT_EQ(first.id(), 1u);
  EXPECT_EQ(first.file(".glb"), directory / "1.glb");
  std::atomic<bool> second_claimed = false;
  std::uint32_t second_id = 0;
  std::thread second([&] {
    server::ModelRegistry::StoreSlot slot = registry.claim("second");
    second_claimed = true;
    second_id = slot.id();
    registry.add(std::move(slot), "second", small_bound_mannequin(), 1);
  });
  // Lookups go on while a slot is held; the second claim waits. 100 ms is ample for an unblocked
  // thread to claim (it only checks a list); a slow machine could only hide a broken lock from
  // this check, never fail a working one.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(second_claimed);
  EXPECT_TRUE(registry.models().empty());
  EXPECT_EQ(registry.add(std::move(first), "first", small_bound_mannequin(), 1)->id, 1u);
  second.join();
  EXPECT_EQ(second_id, 2u) << "ids and files stay in step";
  ASSERT_EQ(registry.models().size(), 2u);
  EXPECT_TRUE(fs::exists(directory / "2.sweepbind"));
  fs::remove_all(directory);
}

// Two threads edit different keys of one model at once: every edit is in the stored model (an
// edit that copied the binding before another was swapped in would drop that one).
TEST(ModelRegistry, ConcurrentEditsOfOneModelAreAllKept) {
  const fs::path directory = fresh_directory("registry_edits");
  server::ModelRegistry registry(directory, 16);
  const std::uint32_t id = add(registry, "edited")->id;
  const std::size_t sweeps = small_bound_mannequin().sweeps.size();
  ASSERT_GE(sweeps, 2u);
  constexpr int kEdits = 12;
  // Thread t sets sweep t's key k to a = 0.01 (k + 1) + t / 1000: each value distinct.
  const auto value = [](int t, int k) { return 0.01f * static_cast<float>(k + 1) + 0.001f * t; };
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < kEdits; ++k) {
        registry.replace(id, [&](deform::BoundModel& bound) {
          auto& keys = bound.sweeps[t].rest_keys;
          keys[k % keys.size()].a = value(t, k);
        });
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  const deform::BoundModel stored = io::load_sweepbind(directory / "1.sweepbind");
  for (int t = 0; t < 2; ++t) {
    const auto& keys = stored.sweeps[t].rest_keys;
    for (int k = kEdits - static_cast<int>(std::min<std::size_t>(keys.size(), kEdits)); k < kEdits;
         ++k) {
      // Exact: the value is set as a float and stored bit for bit.
      EXPECT_EQ(keys[k % keys.size()].a, value(t, k)) << "sweep " << t << " edit " << k;
      EXPECT_EQ(registry.find(id)->bound.sweeps[t].rest_keys[k % keys.size()].a, value(t, k));
    }
  }
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test
