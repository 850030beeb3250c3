// OSC packets read with liblo (server/services/vmc/osc_packet.h): messages and bundles as liblo
// writes them come back whole, nested bundles too; every torn prefix of a message, a bundle torn
// inside an element, a bundle element whose size lies, and seeded random bytes are refused whole
// (nothing handed out).
#include "server/services/vmc/osc_packet.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "tests/server/services/vmc/vmc_packets.h"

namespace sweepd::server {
namespace {

using test::VmcBone;

std::vector<std::byte> bone_packet() {
  return test::osc_bytes(test::vmc_bone_message({"LeftUpperArm", {1, 2, 3}, {0.5f, 0.5f, 0.5f, 0.5f}}),
                         "/VMC/Ext/Bone/Pos");
}

TEST(OscPacket, AMessageIsReadWithItsAddressTypesAndValues) {
  std::vector<std::byte> bytes = bone_packet();
  const auto packet = read_osc_packet(bytes);
  ASSERT_TRUE(packet);
  EXPECT_EQ(packet->bundles, 0u);
  ASSERT_EQ(packet->messages.size(), 1u);
  const OscMessage& message = packet->messages[0];
  EXPECT_EQ(message.address, "/VMC/Ext/Bone/Pos");
  EXPECT_EQ(message.types, "sfffffff");
  EXPECT_STREQ(&message.arguments()[0]->s, "LeftUpperArm");
  EXPECT_EQ(message.arguments()[3]->f, 3.0f);
}

TEST(OscPacket, ABundleGivesItsMessagesInOrderAndNestedBundlesAreRead) {
  lo_bundle frame = test::vmc_frame_bundle({{"Hips"}, {"Spine"}}, 0.5f);
  lo_bundle outer = lo_bundle_new(LO_TT_IMMEDIATE);
  lo_bundle_add_bundle(outer, frame);
  lo_message blend = lo_message_new();
  lo_message_add_string(blend, "Joy");
  lo_message_add_float(blend, 1.0f);
  lo_bundle_add_message(outer, "/VMC/Ext/Blend/Val", blend);
  std::vector<std::byte> bytes = test::bundle_bytes(outer);
  lo_bundle_free_recursive(outer);
  const auto packet = read_osc_packet(bytes);
  ASSERT_TRUE(packet);
  EXPECT_EQ(packet->bundles, 2u);
  std::vector<std::string> addresses;
  for (const OscMessage& message : packet->messages) addresses.push_back(message.address);
  EXPECT_EQ(addresses, (std::vector<std::string>{"/VMC/Ext/Bone/Pos", "/VMC/Ext/Bone/Pos",
                                                 "/VMC/Ext/OK", "/VMC/Ext/T",
                                                 "/VMC/Ext/Blend/Val"}));
}

TEST(OscPacket, EveryTornPrefixOfAMessageIsRefused) {
  const std::vector<std::byte> whole = bone_packet();
  for (std::size_t size = 1; size < whole.size(); ++size) {
    std::vector<std::byte> torn(whole.begin(), whole.begin() + static_cast<long>(size));
    EXPECT_FALSE(read_osc_packet(torn)) << size << " of " << whole.size() << " bytes";
  }
  EXPECT_FALSE(read_osc_packet({})) << "an empty datagram";
}

TEST(OscPacket, ABundleTornInsideAnElementOrLyingAboutASizeIsRefusedWhole) {
  lo_bundle frame = test::vmc_frame_bundle({{"Hips"}, {"Spine"}, {"Chest"}}, 0.5f);
  const std::vector<std::byte> whole = test::bundle_bytes(frame);
  lo_bundle_free_recursive(frame);
  // The element boundaries: after the 16-byte header, each element is its 4-byte size and body.
  std::vector<std::size_t> boundaries = {16};
  while (boundaries.back() < whole.size()) {
    const auto* at = reinterpret_cast<const unsigned char*>(whole.data()) + boundaries.back();
    const std::size_t size = (std::size_t{at[0]} << 24) | (at[1] << 16) | (at[2] << 8) | at[3];
    boundaries.push_back(boundaries.back() + 4 + size);
  }
  ASSERT_EQ(boundaries.back(), whole.size());
  for (std::size_t size = 1; size < whole.size(); ++size) {
    std::vector<std::byte> torn(whole.begin(), whole.begin() + static_cast<long>(size));
    const bool on_boundary = std::ranges::find(boundaries, size) != boundaries.end();
    // Cut between elements, a bundle is a whole, shorter bundle (OSC has no element count).
    EXPECT_EQ(read_osc_packet(torn).has_value(), on_boundary) << size << " bytes";
  }
  std::vector<std::byte> lying = whole;
  lying[16 + 3] = std::byte{0xFC};  // the first element claims 252 bytes: past its message
  EXPECT_FALSE(read_osc_packet(lying));
  lying = whole;
  lying[16 + 3] = std::byte{0x01};  // a size that is not a multiple of 4
  EXPECT_FALSE(read_osc_packet(lying));
}

TEST(OscPacket, SeededRandomBytesAreRefused) {
  std::mt19937 random(51);
  std::uniform_int_distribution<int> byte(0, 255), length(1, 300);
  int refused = 0;
  for (int round = 0; round < 2000; ++round) {
    std::vector<std::byte> bytes(static_cast<std::size_t>(length(random)));
    for (std::byte& b : bytes) b = static_cast<std::byte>(byte(random));
    // Half of them start as OSC does, so that liblo's checks past the first byte are reached.
    if (round % 2 == 0) std::memcpy(bytes.data(), round % 4 == 0 ? "/VMC" : "#bundle", std::min<std::size_t>(bytes.size(), round % 4 == 0 ? 4 : 8));
    refused += read_osc_packet(bytes) ? 0 : 1;
  }
  EXPECT_EQ(refused, 2000);
}

TEST(OscPacket, BundlesNestedTooDeeplyAreRefused) {
  lo_bundle inner = test::vmc_frame_bundle({{"Hips"}}, 0.0f);
  for (int depth = 1; depth < kMaxOscBundleDepth + 1; ++depth) {
    lo_bundle outer = lo_bundle_new(LO_TT_IMMEDIATE);
    lo_bundle_add_bundle(outer, inner);
    inner = outer;
  }
  std::vector<std::byte> bytes = test::bundle_bytes(inner);
  lo_bundle_free_recursive(inner);
  EXPECT_FALSE(read_osc_packet(bytes)) << kMaxOscBundleDepth + 1 << " bundles deep";
}

}  // namespace
}  // namespace sweepd::server
