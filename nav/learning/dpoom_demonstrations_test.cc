#include "nav/learning/dpoom_demonstrations.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "nav/learning/mlp_training.h"
#include "testing/source_dir.h"

namespace corridor::nav {
namespace {

using ::testing::HasSubstr;

const std::filesystem::path kData = testing::SourceDir() / "tests/data/dpoom_bc";
// A cloning short enough for the suite (seconds): corridor-train dpoom's full run is in docs/benchmarks.md.
constexpr float kCloningTestLearningRate = 3e-4F;
constexpr int kCloningTestEpochs = 26;

TEST(DpoomDemonstrationsTest, ReadsARecordingAndLaysItOutAsDpoomsScriptDoes) {
  const std::vector<DpoomRow> rows = ReadDpoomDemonstration(kData / "d3_s3.csv");
  ASSERT_EQ(rows.size(), 1198U);
  EXPECT_NEAR(rows[0].goal_y_m, 9.0276, 1e-4);
  EXPECT_EQ(rows[0].deadends[6], 280.0);
  const Examples examples = DpoomExamples(rows, 4);
  // After the 10 rows left out at the start, a window of 4 rows for each example but the last 4 rows'.
  ASSERT_EQ(examples.size(), static_cast<Eigen::Index>(1198 - 10 - 2 * 4 + 1));
  ASSERT_EQ(examples.inputs.rows(), 48);
  const Eigen::VectorXf first = examples.inputs.col(0);
  const DpoomRow& oldest = rows[10];
  const DpoomRow& newest = rows[13];
  EXPECT_FLOAT_EQ(first(0), static_cast<float>(oldest.deadends[0] / 360.0));
  EXPECT_FLOAT_EQ(first(27), static_cast<float>(newest.deadends[6] / 360.0));
  EXPECT_FLOAT_EQ(first(28), static_cast<float>(oldest.linear_mps));
  EXPECT_FLOAT_EQ(first(35), static_cast<float>(newest.angular_rps));
  EXPECT_FLOAT_EQ(first(36), static_cast<float>(oldest.goal_x_m));
  EXPECT_FLOAT_EQ(first(43), static_cast<float>(newest.goal_y_m));
  EXPECT_FLOAT_EQ(first(47), static_cast<float>(newest.yaw_rad));
  EXPECT_FLOAT_EQ(examples.targets(0, 0), static_cast<float>(rows[14].linear_mps));
  EXPECT_FLOAT_EQ(examples.targets(1, 0), static_cast<float>(rows[14].angular_rps));
  // The person's commands change little from one row to the next: repeating the last is already close.
  EXPECT_NEAR(RepeatLastCommandRmse(examples, 4), 0.0177, 0.0005);
}

TEST(DpoomDemonstrationsTest, BrokenRecordingsAreRefusedNamingTheLine) {
  const auto path = std::filesystem::temp_directory_path() / "corridor-dpoom-test.csv";
  const auto refusal = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      ReadDpoomDemonstration(path);
    } catch (const DemonstrationFileError& e) {
      return std::string(e.what());
    }
    return std::string("(read)");
  };
  const std::string header = "time,goal_x,goal_y,linear_x,angular_z,yaw,deadends\n";
  const std::string row = "1.7,0.1,9.0,0.0,0.0,1.58,340,360,360,340,340,360,280\n";
  EXPECT_EQ(refusal(header + row + row), "(read)");
  EXPECT_THAT(refusal(row), HasSubstr("line 1: want the header"));
  EXPECT_THAT(refusal(header + row + "1.7,0.1,x,0.0,0.0,1.58,340,360,360,340,340,360,280\n"),
              HasSubstr("line 3: 'x' is not a number"));
  EXPECT_THAT(refusal(header + "1.7,0.1,9.0\n"), HasSubstr("line 2: want 13 numbers"));
  EXPECT_THAT(refusal(header + "1.7,0.1,9.0,0.0,0.0,1.58,340,360,360,340,340,360,280,5\n"),
              HasSubstr("line 2: want 13 numbers"));
  std::filesystem::remove(path);
  EXPECT_THAT(refusal(""), HasSubstr("line 1"));
  std::filesystem::remove(path);
  EXPECT_THROW(ReadDpoomDemonstration(path), DemonstrationFileError);
}

TEST(DpoomDemonstrationsTest, ACloneOfThePersonPredictsTheirNextCommandBetterThanRepeatingTheirLast) {
  // The paper's split (d3_s3 held out); of the other recordings' examples, 30 % held out at random (DPoom's test set).
  // A short training for the suite: corridor-train dpoom's full runs are in docs/benchmarks.md.
  Examples recorded;
  for (const auto& entry : std::filesystem::directory_iterator(kData)) {
    if (entry.path().extension() != ".csv" || entry.path().filename() == "d3_s3.csv") continue;
    recorded.Append(DpoomExamples(ReadDpoomDemonstration(entry.path()), 4));
  }
  ASSERT_GT(recorded.size(), 20000);
  const auto [train, test] = SplitExamples(recorded, 0.3, 1);
  EXPECT_EQ(test.size(), static_cast<Eigen::Index>(std::round(0.3 * static_cast<double>(recorded.size()))));
  EXPECT_EQ(train.size() + test.size(), recorded.size());
  Mlp net = DpoomNetwork(48, 1);
  TrainingOptions options;
  options.adam.learning_rate = kCloningTestLearningRate;
  MlpTrainer trainer(net, options);
  const double before = std::sqrt(Evaluate(net, Loss::kMeanSquared, test.inputs, test.targets));
  double after = before;  // the best epoch's, as DPoom's script keeps the best checkpoint on its test set
  for (int epoch = 0; epoch < kCloningTestEpochs; ++epoch) {
    trainer.Epoch(train.inputs, train.targets);
    after = std::min(after, std::sqrt(Evaluate(net, Loss::kMeanSquared, test.inputs, test.targets)));
  }
  const double repeat = RepeatLastCommandRmse(test, 4);
  EXPECT_GT(before, 3.0 * repeat);
  EXPECT_LT(after, repeat) << "from " << before;
}

}  // namespace
}  // namespace corridor::nav
