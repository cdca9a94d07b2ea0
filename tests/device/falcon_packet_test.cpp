#include "device/falcon/falcon_packet.h"
#include <gtest/gtest.h>

using namespace hb;

TEST(FalconPacketTest, CommandRoundTrip) {
  for (std::int16_t m : {0, 1, -1, 4096, -4096, 1234, -3000}) {
    FalconCommand c;
    c.motor = {m, static_cast<std::int16_t>(-m), 7};
    c.homing_mode = m % 2 != 0;
    c.leds = 0x5;
    FalconPacket p;
    encode_command(c, p);
    EXPECT_EQ(p[0], '<');
    EXPECT_EQ(p[15], '>');
    for (int i = 1; i < 15; ++i) {
      EXPECT_GE(p[i], 'A');
      EXPECT_LE(p[i], 'P');
    }
    FalconCommand d;
    ASSERT_TRUE(decode_command(p, d));
    EXPECT_EQ(d.motor, c.motor);
    EXPECT_EQ(d.homing_mode, c.homing_mode);
    EXPECT_EQ(d.leds, c.leds);
  }
}

TEST(FalconPacketTest, ReportRoundTrip) {
  FalconReport r;
  r.encoder = {-32768, 32767, -5};
  r.homed = 0x5;
  r.buttons = 0xA;
  FalconPacket p;
  encode_report(r, p);
  FalconReport s;
  ASSERT_TRUE(decode_report(p, s));
  EXPECT_EQ(s.encoder, r.encoder);
  EXPECT_EQ(s.homed, r.homed);
  EXPECT_EQ(s.buttons, r.buttons);
}

TEST(FalconPacketTest, MotorCommandsAreCappedAt4096) {
  FalconCommand c;
  c.motor = {30000, -30000, 4097};
  FalconPacket p;
  encode_command(c, p);
  FalconCommand d;
  ASSERT_TRUE(decode_command(p, d));
  EXPECT_EQ(d.motor[0], 4096);
  EXPECT_EQ(d.motor[1], -4096);
  EXPECT_EQ(d.motor[2], 4096);
}

TEST(FalconPacketTest, CorruptNibbleOrFrameIsRejected) {
  FalconReport r;
  FalconPacket p;
  encode_report(r, p);
  FalconPacket bad = p;
  bad[5] = 'Z';
  FalconReport out;
  out.buttons = 3;
  EXPECT_FALSE(decode_report(bad, out));
  EXPECT_EQ(out.buttons, 3);  // unchanged
  bad = p;
  bad[0] = 'A';
  EXPECT_FALSE(decode_report(bad, out));
  bad = p;
  bad[15] = '<';
  EXPECT_FALSE(decode_report(bad, out));
}
