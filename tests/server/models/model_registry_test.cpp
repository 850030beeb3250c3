// ModelRegistry without a process: the store's restore after a damaged entry, ids never reused,
// and a StoreSlot keeping a second load out until the first is stored.
#include "server/models/model_registry.h"

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <thread>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
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

TEST(ModelRegistry, RestoreKeepsGoodEntriesAndReportsADamagedOne) {
  const fs::path directory = fresh_directory("registry");
  {
    server::ModelRegistry registry(directory, 16);
    add(registry, "first");
    add(registry, "second");
  }
  // Damage the first model's file: one flipped payload byte fails its checksum.
  {
    std::fstream file(directory / "1.sweepbind", std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(100);
    file.put('\x7f');
  }
  server::ModelRegistry registry(directory, 16);
  const std::vector<std::string> problems = registry.restore();
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("1.sweepbind"), std::string::npos) << problems[0];
  ASSERT_EQ(registry.models().size(), 1u);
  EXPECT_EQ(registry.models()[0]->name, "second");
  EXPECT_EQ(registry.models()[0]->id, 2u);
  // New ids never reuse an old one, even a dropped one.
  EXPECT_EQ(add(registry, "third")->id, 3u);
  EXPECT_EQ(registry.find(std::string_view("third"))->id, 3u);
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

}  // namespace
}  // namespace sweepd::test
