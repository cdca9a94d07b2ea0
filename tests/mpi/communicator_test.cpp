// The core's side of the MPI layer: the serial communicator and the dealing schedule.
#include "parallel/byte_buffer.h"
#include "parallel/communicator.h"
#include "parallel/work_split.h"
#include <gtest/gtest.h>
#include <vector>

TEST(DealtChunksTest, EveryItemBelongsToExactlyOneRankInTurn) {
  for (std::size_t count : {0u, 1u, 7u, 1000u, 1001u})
    for (int ranks : {1, 2, 3, 8}) {
      const hb::DealtChunks deal{count, hb::deal_chunk_size(count, ranks, 4, 3), ranks};
      std::vector<int> owner(count, -1);
      std::size_t total = 0;
      for (int r = 0; r < ranks; ++r) {
        std::size_t previous_end = 0;
        deal.for_each_of(r, [&](std::size_t first, std::size_t last) {
          EXPECT_LE(previous_end, first);
          previous_end = last;
          for (std::size_t i = first; i < last; ++i) {
            EXPECT_EQ(owner[i], -1) << "item " << i << " dealt twice";
            owner[i] = r;
          }
        });
        total += deal.items_of(r);
      }
      EXPECT_EQ(total, count);
      for (std::size_t i = 0; i < count; ++i) EXPECT_NE(owner[i], -1) << "item " << i << " not dealt";
      // Shares differ by at most one chunk.
      if (count > 0 && ranks > 1) {
        EXPECT_LE(deal.items_of(0) - deal.items_of(ranks - 1), deal.chunk);
      }
    }
}

TEST(SerialCommunicatorTest, CollectivesReturnTheProcessOwnData) {
  hb::Communicator& comm = hb::serial_communicator();
  EXPECT_EQ(comm.rank(), 0);
  EXPECT_EQ(comm.size(), 1);
  const hb::Bytes mine = {1, 2, 3};
  ASSERT_EQ(comm.gather(mine).size(), 1u);
  EXPECT_EQ(comm.gather(mine)[0], mine);
  EXPECT_EQ(comm.all_gather(mine)[0], mine);
  hb::Bytes b = mine;
  comm.broadcast(b);
  EXPECT_EQ(b, mine);
  EXPECT_EQ(comm.sum(2.5), 2.5);
  EXPECT_EQ(comm.sum(std::uint64_t(7)), 7u);
  EXPECT_EQ(comm.bytes_sent(), 0u);
}

TEST(ByteBufferTest, ReadsBackWhatWasWrittenAndRejectsAShortMessage) {
  hb::ByteWriter w;
  w.put(std::uint32_t(42));
  w.put_vector(std::vector<float>{1.f, 2.f});
  w.put_string("rank");
  hb::ByteReader r(w.bytes(), "test");
  EXPECT_EQ(r.get<std::uint32_t>(), 42u);
  EXPECT_EQ(r.get_vector<float>(), (std::vector<float>{1.f, 2.f}));
  EXPECT_EQ(r.get_string(), "rank");
  EXPECT_TRUE(r.at_end());
  EXPECT_THROW(r.get<std::uint8_t>(), hb::InvalidInput);
}
