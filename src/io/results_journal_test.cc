#include "mcpose/results_journal.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "mcpose/io_util.h"
#include "io/results_csv.h"
#include "test_data.h"

namespace mcpose::io {
namespace {

std::vector<PoseResult> Rows(int scene, int image, std::initializer_list<int> objs) {
  std::vector<PoseResult> rows;
  for (int obj : objs) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.1 * obj, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    rows.push_back({scene, image, obj, 0.123456789 * obj, SE3(R, Eigen::Vector3d(0.01 * obj, -0.02, 0.8)), 0.5});
  }
  return rows;
}

TEST(ResultsJournalTest, ResumeKeepsFinishedImagesAndDropsACutOne) {
  const auto dir = testing::TempDir("journal_resume");
  const std::string out = (dir / "r.csv").string();
  {
    auto j = ResultsJournal::Open(out, "abc", /*resume=*/false);
    ASSERT_TRUE(j.ok()) << j.status().ToString();
    ASSERT_TRUE((*j)->Append({49, 2}, Rows(49, 2, {3, 6})).ok());
    ASSERT_TRUE((*j)->Append({49, 1}, Rows(49, 1, {9})).ok());
  }
  // A kill in the middle of the next image: a row and half of another, no end mark.
  std::ofstream(JournalPath(out), std::ios::app) << ResultsCsvRow(Rows(49, 3, {3})[0]) << "\n49,3,6,0.5,1 0";
  auto j = ResultsJournal::Open(out, "abc", /*resume=*/true);
  ASSERT_TRUE(j.ok()) << j.status().ToString();
  EXPECT_EQ((*j)->kept_images(), 2);
  EXPECT_TRUE((*j)->Has({49, 1}) && (*j)->Has({49, 2}) && !(*j)->Has({49, 3}));
  ASSERT_TRUE((*j)->Append({49, 3}, Rows(49, 3, {3, 6})).ok());
  ASSERT_TRUE((*j)->Finish().ok());
  EXPECT_FALSE(std::filesystem::exists(JournalPath(out)));

  // The CSV: every row once, sorted, equal to a direct write of the same rows.
  std::vector<PoseResult> all = Rows(49, 1, {9});
  for (const auto& r : Rows(49, 2, {3, 6})) all.push_back(r);
  for (const auto& r : Rows(49, 3, {3, 6})) all.push_back(r);
  const std::string direct = (dir / "direct.csv").string();
  ASSERT_TRUE(WriteResultsCsv(direct, all).ok());
  const StatusOr<std::string> got = ReadFileToString(out), want = ReadFileToString(direct);
  ASSERT_TRUE(got.ok() && want.ok());
  EXPECT_EQ(*got, *want);
}

TEST(ResultsJournalTest, RefusesAnotherRunsJournalAndBadLines) {
  const std::string out = (testing::TempDir("journal_refuse") / "r.csv").string();
  {
    auto j = ResultsJournal::Open(out, "abc", false);
    ASSERT_TRUE(j.ok());
    ASSERT_TRUE((*j)->Append({1, 1}, Rows(1, 1, {2})).ok());
  }
  auto other = ResultsJournal::Open(out, "def", true);
  ASSERT_FALSE(other.ok());
  EXPECT_EQ(other.status().message(), JournalPath(out) +
            ": was written by a run with other options, detections, dataset or mcpose version; rerun without "
            "--resume to start afresh");
  // A fresh start replaces it.
  auto fresh = ResultsJournal::Open(out, "def", false);
  ASSERT_TRUE(fresh.ok());
  EXPECT_EQ((*fresh)->kept_images(), 0);
  fresh->reset();

  std::ofstream(JournalPath(out)) << "# mcpose results journal abc\n1,1,2,0.5,1 0 0 0 1 0 0 0 1,1 2 3,0.1\n"
                                     "# done 1 1 2\n";
  auto bad = ResultsJournal::Open(out, "abc", true);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().message(), JournalPath(out) +
            ": line 3: the rows before this end mark are not the 2 rows of scene_id 1, im_id 1");
}

// Kept images and rows must belong to the run's detections.
TEST(ResultsJournalTest, KeptRowsMustBelongToTheDetections) {
  const std::string out = (testing::TempDir("journal_belong") / "r.csv").string();
  const std::vector<Detection> dets = {{49, 1, 3, 0.9, 1, 1, 10, 10}, {49, 1, 6, 0.9, 1, 1, 10, 10},
                                       {49, 2, 3, 0.9, 1, 1, 10, 10}};
  const auto journal_of = [&](const std::vector<std::pair<FrameKey, std::vector<PoseResult>>>& blocks) {
    {
      auto j = ResultsJournal::Open(out, "abc", false);
      EXPECT_TRUE(j.ok());
      for (const auto& [key, rows] : blocks) EXPECT_TRUE((*j)->Append(key, rows).ok());
    }
    auto j = ResultsJournal::Open(out, "abc", true);
    EXPECT_TRUE(j.ok()) << j.status().ToString();
    return (*j)->CheckKeptAgainst(dets);
  };
  EXPECT_TRUE(journal_of({{{49, 1}, Rows(49, 1, {3, 6})}, {{49, 2}, Rows(49, 2, {3})}}).ok());
  EXPECT_TRUE(journal_of({{{49, 1}, Rows(49, 1, {6})}}).ok());  // a class without depth has no row
  const std::string path = JournalPath(out);
  EXPECT_EQ(journal_of({{{49, 5}, Rows(49, 5, {3})}}).message(),
            path + ": the rows of scene_id 49, im_id 5: no detection names this image");
  EXPECT_EQ(journal_of({{{49, 2}, Rows(49, 2, {3, 6})}}).message(),
            path + ": the rows of scene_id 49, im_id 2: a row of obj_id 6, which no detection of this image names");
  EXPECT_EQ(journal_of({{{49, 1}, Rows(49, 1, {3, 3})}}).message(),
            path + ": the rows of scene_id 49, im_id 1: more rows of obj_id 3 than its 1 box(es) in this image");
  // Two boxes of a class, two instances: two rows.
  std::vector<Detection> two = dets;
  two.push_back({49, 1, 3, 0.5, 50, 50, 10, 10});
  {
    auto j = ResultsJournal::Open(out, "abc", true);
    ASSERT_TRUE(j.ok());
    EXPECT_TRUE((*j)->CheckKeptAgainst(two).ok());
  }
}

TEST(ResultsJournalTest, TornTailAfterTheLastImageIsDroppedButNotABadLineBeforeOne) {
  const std::string out = (testing::TempDir("journal_torn") / "r.csv").string();
  const std::string head = "# mcpose results journal abc\n" + ResultsCsvRow(Rows(1, 1, {2})[0]) + "\n# done 1 1 1\n";
  // A power loss: a flushed image, then a block of zeros and a stale row's tail.
  std::ofstream(JournalPath(out), std::ios::binary)
      << head << std::string(64, '\0') << "\n" << ResultsCsvRow(Rows(1, 2, {4})[0]).substr(7) << "\n";
  {
    auto j = ResultsJournal::Open(out, "abc", true);
    ASSERT_TRUE(j.ok()) << j.status().ToString();
    EXPECT_EQ((*j)->kept_images(), 1);
    ASSERT_TRUE((*j)->Append({1, 2}, Rows(1, 2, {4})).ok());
  }
  const StatusOr<std::string> text = ReadFileToString(JournalPath(out));
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(*text, head + ResultsCsvRow(Rows(1, 2, {4})[0]) + "\n# done 1 2 1\n");  // the torn part is gone

  // A bad line with a finished image after it is damage, not a torn tail.
  std::ofstream(JournalPath(out), std::ios::binary)
      << head << "1,2,4,garbage\n" << ResultsCsvRow(Rows(1, 3, {5})[0]) << "\n# done 1 3 1\n";
  auto bad = ResultsJournal::Open(out, "abc", true);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().message(), JournalPath(out) + ": line 4: expected 7 comma-separated fields, got 4");
}

TEST(ResultsJournalTest, OneRunAtATime) {
  const std::string out = (testing::TempDir("journal_lock") / "r.csv").string();
  auto first = ResultsJournal::Open(out, "abc", false);
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE((*first)->Append({1, 1}, Rows(1, 1, {2})).ok());
  for (const bool resume : {false, true}) {
    auto second = ResultsJournal::Open(out, "abc", resume);
    ASSERT_FALSE(second.ok());
    EXPECT_EQ(second.status().message(),
              JournalPath(out) + ": in use by another run writing " + out + " (wait for it or stop it)");
  }
  first->reset();  // the first run ends (killed): its image is there for the next
  auto next = ResultsJournal::Open(out, "abc", true);
  ASSERT_TRUE(next.ok()) << next.status().ToString();
  EXPECT_EQ((*next)->kept_images(), 1);
}

TEST(ResultsJournalTest, FingerprintIsOptionsButThreadsDetectionsAndSource) {
  const auto dir = testing::TempDir("journal_fingerprint");
  std::filesystem::create_directories(dir / "data" / "models");
  const RunSource source{(dir / "data").string(), "test", (dir / "data" / "models").string()};
  EstimatorOptions a, b;
  b.engine.threads = 7;
  std::vector<Detection> dets(1);
  const std::string base = RunFingerprint(a, dets, source);
  EXPECT_EQ(base, RunFingerprint(b, dets, source));
  b.seed = 1;
  EXPECT_NE(base, RunFingerprint(b, dets, source));
  std::vector<Detection> moved = dets;
  moved[0].x += 1e-9;
  EXPECT_NE(base, RunFingerprint(a, moved, source));
  // The same folders named another way are the same source; another folder, split or models
  // folder is another.
  RunSource same = source;
  same.dataset_root = (dir / "data" / "models" / "..").string() + "/";
  EXPECT_EQ(base, RunFingerprint(a, dets, same));
  RunSource other_root = source, other_split = source, other_models = source;
  other_root.dataset_root = dir.string();
  other_split.split = "train";
  other_models.models_dir = (dir / "data").string();
  EXPECT_NE(base, RunFingerprint(a, dets, other_root));
  EXPECT_NE(base, RunFingerprint(a, dets, other_split));
  EXPECT_NE(base, RunFingerprint(a, dets, other_models));
}

}  // namespace
}  // namespace mcpose::io
