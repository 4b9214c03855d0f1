// What the learned policies' networks cost on one core (issue 40's targets: a MORP-IL step <= 0.1 ms, the direction
// network's <= 1 ms): one forward pass of MORP-IL's layers (48-48-96-144-48-2, DPoom's code) and of Takiguchi's
// direction network (274 inputs, 20 classes) at the paper's width (3 x 2048) and narrower ones, each beside the same
// layers in OpenCV's dnn module (built from the same weights); the direction network's inputs made from what a laser
// shows; and one training step (a batch of 32, Adam) of MORP-IL, which sets how long corridor-train takes.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include <opencv2/dnn.hpp>

#include "nav/learning/dpoom_demonstrations.h"
#include "nav/learning/mlp_training.h"
#include "nav/policy/takiguchi.h"
#include "testing/opencv_mlp.h"

namespace corridor::nav {
namespace {

Mlp MorpIl() { return DpoomNetwork(48, 1); }

Mlp Direction(int width) {
  return Mlp::Random(std::array{274, width, width, width, 20},
                     std::array{Activation::kRelu, Activation::kRelu, Activation::kRelu, Activation::kSoftmax}, 1);
}

Eigen::VectorXf Input(int size) {
  std::mt19937 random(3);
  std::normal_distribution<float> normal;
  Eigen::VectorXf x(size);
  for (Eigen::Index i = 0; i < size; ++i) x(i) = normal(random);
  return x;
}

void TimeForward(benchmark::State& state, const Mlp& net) {
  const Eigen::VectorXf x = Input(net.inputs());
  for (auto _ : state) benchmark::DoNotOptimize(net.Forward(x));
}

// The same layers in OpenCV's dnn module.
void TimeOpenCv(benchmark::State& state, const Mlp& mlp) {
  cv::dnn::Net net = testing::OpenCvMlp(mlp);
  const Eigen::VectorXf x = Input(mlp.inputs());
  const cv::Mat blob(1, mlp.inputs(), CV_32F, const_cast<float*>(x.data()));
  for (auto _ : state) {
    net.setInput(blob);
    benchmark::DoNotOptimize(net.forward());
  }
}

void BM_MorpIlForward(benchmark::State& state) { TimeForward(state, MorpIl()); }
void BM_MorpIlForwardOpenCv(benchmark::State& state) { TimeOpenCv(state, MorpIl()); }
void BM_DirectionForward(benchmark::State& state) { TimeForward(state, Direction(static_cast<int>(state.range(0)))); }
void BM_DirectionForwardOpenCv(benchmark::State& state) {
  TimeOpenCv(state, Direction(static_cast<int>(state.range(0))));
}

// Takiguchi's 274 inputs from what a laser shows round a robot in a corridor: two walls' 360 points and five people.
void BM_DirectionInputs(benchmark::State& state) {
  Surroundings around;
  for (int i = 0; i < 180; ++i) {
    around.static_points.emplace_back(-4.0 + 0.05 * i, 1.2);
    around.static_points.emplace_back(-4.0 + 0.05 * i, -1.2);
  }
  for (int i = 0; i < 5; ++i) {
    TrackedObject person;
    person.position = {0.8 * i - 0.5, 0.3 * (i % 3) - 0.3};
    person.velocity = {-0.8, 0.1 * i};
    person.radius_m = 0.25;
    person.moving = true;
    around.objects.push_back(person);
  }
  const TakiguchiOptions options;
  for (auto _ : state) benchmark::DoNotOptimize(TakiguchiInput(Pose2{0.0, 0.0, 0.3}, around, 0.2, options));
}

void BM_MorpIlTrainingStep(benchmark::State& state) {
  Mlp net = MorpIl();
  MlpTrainer trainer(net, TrainingOptions{});
  std::mt19937 random(5);
  std::normal_distribution<float> normal;
  Eigen::MatrixXf x(48, 32);
  Eigen::MatrixXf y(2, 32);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = normal(random);
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) = normal(random);
  for (auto _ : state) benchmark::DoNotOptimize(trainer.Step(x, y));
}

BENCHMARK(BM_MorpIlForward);
BENCHMARK(BM_MorpIlForwardOpenCv);
BENCHMARK(BM_DirectionForward)->Arg(2048)->Arg(512)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DirectionForwardOpenCv)->Arg(2048)->Arg(512)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DirectionInputs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MorpIlTrainingStep)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace corridor::nav

BENCHMARK_MAIN();
