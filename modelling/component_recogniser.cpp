// ComponentRecogniser (modelling/components.h): the colour path's perceptron, trained from the
// catalogue alone (paper §3.4), its file and its scores.
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "common/error.h"
#include "modelling/component_features.h"

namespace mopad::modelling {
namespace {

// Samples of every class then "none" (label = class count): stream (seed, stream, class).
void MakeSamples(const interfaces::ObjectModelCatalogue& cat, const ComponentTrainingParams& p,
                 int per_class, std::uint64_t seed, const char* stream,
                 std::vector<ColourPattern>& x, std::vector<int>& y) {
  const int n = static_cast<int>(cat.models.size());
  for (int k = 0; k < n; ++k) {
    CounterRng rng(seed, stream, static_cast<std::uint64_t>(k));
    for (int i = 0; i < per_class; ++i) {
      const AugmentedBox b = AugmentModel(cat.models[static_cast<std::size_t>(k)], p, rng);
      x.push_back(ComputeColourPattern(b.rgb, b.width_m, b.height_m, p.lightness));
      y.push_back(k);
    }
  }
  CounterRng rng(seed, stream, static_cast<std::uint64_t>(n));
  for (int i = 0; i < 3 * per_class; ++i) {
    const auto& m = cat.models[static_cast<std::size_t>(i) % cat.models.size()];
    const AugmentedBox b = AugmentNegative(m, i % 3, p, rng);
    x.push_back(ComputeColourPattern(b.rgb, b.width_m, b.height_m, p.lightness));
    y.push_back(n);
  }
}

}  // namespace

void ComponentTrainingParams::Validate() const {
  ValidateParams(*this, "component_training.");
  if (pixel_min > pixel_max)
    throw InputError("", "parameter 'component_training.pixel_min' exceeds 'pixel_max'",
                     std::to_string(pixel_min), "<= " + std::to_string(pixel_max));
}

cv::Mat ComponentRecogniser::Impl::Standardise(const ColourPattern& f) const {
  cv::Mat row(1, kPatternSize, CV_32F);
  for (int i = 0; i < kPatternSize; ++i) row.at<float>(0, i) = (f[i] - mean[i]) / scale[i];
  return row;
}

std::vector<float> ComponentRecogniser::Impl::Score(const ColourPattern& f) const {
  cv::Mat out;
  mlp->predict(Standardise(f), out);
  auto at = [&](int i) { return std::clamp(0.5f * (out.at<float>(0, i) + 1.0f), 0.0f, 1.0f); };
  std::vector<float> s;
  for (int g : group) s.push_back(at(g));
  s.push_back(at(groups));
  return s;
}

ComponentRecogniser::ComponentRecogniser() : impl_(std::make_unique<Impl>()) {}
ComponentRecogniser::~ComponentRecogniser() = default;
ComponentRecogniser::ComponentRecogniser(ComponentRecogniser&&) noexcept = default;
ComponentRecogniser& ComponentRecogniser::operator=(ComponentRecogniser&&) noexcept = default;

bool ComponentRecogniser::Trained() const { return impl_ && impl_->mlp && impl_->mlp->isTrained(); }
const interfaces::ObjectModelCatalogue& ComponentRecogniser::Catalogue() const {
  return impl_->catalogue;
}

ComponentRecogniser ComponentRecogniser::Train(const interfaces::ObjectModelCatalogue& catalogue,
                                               const ComponentTrainingParams& params) {
  params.Validate();
  if (catalogue.models.empty())
    throw InputError("", "object-model catalogue is empty", "0 models", "at least one model");
  for (const auto& m : catalogue.models) ModelMissMask(m);  // InputError without images
  ComponentRecogniser r;
  r.impl_->catalogue = catalogue;
  r.impl_->training = params;
  std::vector<ColourPattern> x;
  std::vector<int> y;
  MakeSamples(catalogue, params, params.samples_per_class, params.seed, "sm5_train", x, y);
  r.impl_->group = LookAlikeGroups(catalogue);
  r.impl_->groups = *std::max_element(r.impl_->group.begin(), r.impl_->group.end()) + 1;
  const int n = static_cast<int>(x.size()), classes = r.impl_->groups + 1;
  const int none = static_cast<int>(catalogue.models.size());
  for (int i = 0; i < kPatternSize; ++i) {
    double s = 0, s2 = 0;
    for (const auto& f : x) s += f[i], s2 += static_cast<double>(f[i]) * f[i];
    const double m = s / n, var = std::max(0.0, s2 / n - m * m);
    r.impl_->mean[i] = static_cast<float>(m);
    r.impl_->scale[i] = static_cast<float>(std::max(1e-6, std::sqrt(var)));
  }
  cv::Mat samples(n, kPatternSize, CV_32F), targets(n, classes, CV_32F, cv::Scalar(-1.0f));
  for (int i = 0; i < n; ++i) {
    r.impl_->Standardise(x[static_cast<std::size_t>(i)]).copyTo(samples.row(i));
    const int yi = y[static_cast<std::size_t>(i)];
    targets.at<float>(
        i, yi == none ? r.impl_->groups : r.impl_->group[static_cast<std::size_t>(yi)]) = 1.0f;
  }
  // On-line back-propagation runs on the calling thread alone in OpenCV 4.6 (only RPROP sums
  // over parallel ranges), its initial weights from that thread's cv::theRNG(): the weights
  // are the same on any thread and while other threads use OpenCV. (The global thread count
  // is left alone: setting it from one thread races with the others' parallel loops.)
  cv::theRNG().state = Mix64(params.seed ^ HashName("sm5_mlp_init"));
  auto mlp = cv::ml::ANN_MLP::create();
  mlp->setLayerSizes(std::vector<int>{kPatternSize, params.hidden, classes});
  mlp->setActivationFunction(cv::ml::ANN_MLP::SIGMOID_SYM, 0.0, 0.0);
  // On-line back-propagation (rate 0.01, momentum 0.1): RPROP of OpenCV 4.6 reached a far worse
  // held-out accuracy on these patterns (docs/models.md, SM5).
  mlp->setTrainMethod(cv::ml::ANN_MLP::BACKPROP, 0.01, 0.1);
  mlp->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, params.iterations, 0.0));
  mlp->train(cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, targets));
  r.impl_->mlp = mlp;
  return r;
}

void ComponentRecogniser::Save(const std::string& path) const {
  if (!Trained()) throw InputError(path, "recogniser is not trained", "untrained", "trained");
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw InputError(path, "cannot write the recogniser", "", "a writable file");
  fs << "format"
     << "mopad-sm5-recogniser"
     << "version" << 1;
  fs << "lightness" << (impl_->training.lightness ? 1 : 0);
  fs << "classes"
     << "[";
  for (const auto& m : impl_->catalogue.models) fs << m.class_name;
  fs << "]";
  fs << "mean" << std::vector<float>(impl_->mean.begin(), impl_->mean.end());
  fs << "scale" << std::vector<float>(impl_->scale.begin(), impl_->scale.end());
  fs << "mlp"
     << "{";
  impl_->mlp->write(fs);
  fs << "}";
}

ComponentRecogniser ComponentRecogniser::Load(const interfaces::ObjectModelCatalogue& catalogue,
                                              const std::string& path) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw InputError(path, "malformed recogniser file", e.what(), "OpenCV FileStorage YAML");
  }
  if (!fs.isOpened()) throw InputError(path, "cannot read the recogniser", "", "a readable file");
  if (static_cast<std::string>(fs["format"]) != "mopad-sm5-recogniser")
    throw InputError(path, "not a recogniser file", static_cast<std::string>(fs["format"]),
                     "format mopad-sm5-recogniser");
  std::vector<std::string> classes;
  fs["classes"] >> classes;
  std::vector<std::string> expected;
  for (const auto& m : catalogue.models) expected.push_back(m.class_name);
  if (classes != expected)
    throw InputError(path, "recogniser classes differ from the catalogue's",
                     std::to_string(classes.size()) + " classes",
                     std::to_string(expected.size()) + " classes in catalogue order");
  std::vector<float> mean, scale;
  fs["mean"] >> mean;
  fs["scale"] >> scale;
  if (mean.size() != kPatternSize || scale.size() != kPatternSize)
    throw InputError(path, "recogniser standardisation has the wrong size",
                     std::to_string(mean.size()), std::to_string(kPatternSize));
  ComponentRecogniser r;
  r.impl_->catalogue = catalogue;
  r.impl_->training.lightness = static_cast<int>(fs["lightness"]) != 0;
  std::copy(mean.begin(), mean.end(), r.impl_->mean.begin());
  std::copy(scale.begin(), scale.end(), r.impl_->scale.begin());
  r.impl_->group = LookAlikeGroups(catalogue);
  r.impl_->groups = *std::max_element(r.impl_->group.begin(), r.impl_->group.end()) + 1;
  r.impl_->mlp = cv::ml::ANN_MLP::create();
  r.impl_->mlp->read(fs["mlp"]);
  const cv::Mat layers = r.impl_->mlp->getLayerSizes();
  if (layers.total() < 2 || layers.at<int>(0) != kPatternSize ||
      layers.at<int>(static_cast<int>(layers.total()) - 1) != r.impl_->groups + 1)
    throw InputError(path, "recogniser network has the wrong layer sizes", "",
                     "14 in, classes+1 out");
  return r;
}

std::vector<float> ComponentRecogniser::Score(const std::vector<std::uint8_t>& rgb, int width,
                                              int height, double width_m, double height_m) const {
  if (!Trained()) throw InputError("", "recogniser is not trained", "untrained", "trained");
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
    throw InputError("", "colour box size mismatch", std::to_string(rgb.size()) + " bytes",
                     "width * height * 3 with width, height > 0");
  const cv::Mat img(height, width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data()));
  return impl_->Score(ComputeColourPattern(img, width_m, height_m, impl_->training.lightness));
}

std::vector<double> ComponentRecogniser::ClassAccuracy(int samples_per_class,
                                                       std::uint64_t seed) const {
  if (!Trained()) throw InputError("", "recogniser is not trained", "untrained", "trained");
  std::vector<ColourPattern> x;
  std::vector<int> y;
  MakeSamples(impl_->catalogue, impl_->training, samples_per_class, seed, "sm5_holdout", x, y);
  const int none = static_cast<int>(impl_->group.size());
  const auto grp = [&](int k) {
    return k == none ? -1 : impl_->group[static_cast<std::size_t>(k)];
  };
  std::vector<double> right(static_cast<std::size_t>(none) + 1, 0.0), total = right;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::vector<float> s = impl_->Score(x[i]);
    const int best = static_cast<int>(std::max_element(s.begin(), s.end()) - s.begin());
    right[static_cast<std::size_t>(y[i])] += grp(best) == grp(y[i]) ? 1 : 0;
    total[static_cast<std::size_t>(y[i])] += 1;
  }
  for (std::size_t k = 0; k < right.size(); ++k)
    right[k] = total[k] > 0 ? right[k] / total[k] : 0.0;
  return right;
}

double ComponentRecogniser::Accuracy(int samples_per_class, std::uint64_t seed) const {
  const std::vector<double> a = ClassAccuracy(samples_per_class, seed);
  // Samples: samples_per_class of each class, 3 x samples_per_class of "none".
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < a.size(); ++k) sum += a[k];
  sum += 3.0 * a.back();
  return sum / (static_cast<double>(a.size()) + 2.0);
}

}  // namespace mopad::modelling
