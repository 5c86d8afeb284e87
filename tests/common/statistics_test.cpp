#include "common/statistics.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace mopad {
namespace {

TEST(Median, OddCountIsTheMiddleValueWhateverTheOrder) {
  EXPECT_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(Median({5.0}), 5.0);
  EXPECT_EQ(Median({-1.0, 7.0, 7.0, 0.5, 2.0}), 2.0);
}

TEST(Median, EvenCountIsTheMeanOfTheTwoMiddleValues) {
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(Median({1.0, 2.0}), 1.5);
  EXPECT_EQ(Median({0.1, 0.2}), 0.5 * (0.1 + 0.2));  // the mean as computed, to the last bit
}

TEST(Median, EmptyInputThrows) { EXPECT_THROW(Median({}), std::invalid_argument); }

TEST(UpperMedian, EvenCountIsTheHigherMiddleValueNotAMean) {
  EXPECT_EQ(UpperMedian(std::vector<double>{4.0, 1.0, 3.0, 2.0}), 3.0);
  EXPECT_EQ(UpperMedian(std::vector<float>{2.0f, 1.0f}), 2.0f);
  EXPECT_EQ(UpperMedian(std::vector<std::uint32_t>{9, 1, 5, 7}), 7u);
}

TEST(UpperMedian, OddCountIsTheMedian) {
  EXPECT_EQ(UpperMedian(std::vector<double>{3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(UpperMedian(std::vector<int>{8}), 8);
}

TEST(UpperMedian, EmptyInputThrows) {
  EXPECT_THROW(UpperMedian(std::vector<double>{}), std::invalid_argument);
}

TEST(Quantile, IsTheElementAtFloorOfQTimesNMinusOne) {
  const std::vector<double> v = {50, 40, 30, 20, 10, 0, 90, 80, 70, 60, 100};  // 0..100 step 10
  EXPECT_EQ(Quantile(v, 0.0), 0.0);
  EXPECT_EQ(Quantile(v, 1.0), 100.0);
  EXPECT_EQ(Quantile(v, 0.95), 90.0);  // floor(9.5) = 9
  EXPECT_EQ(Quantile(v, 0.5), 50.0);
  // Even count: q = 0.5 is the lower median, no interpolation.
  EXPECT_EQ(Quantile(std::vector<double>{4.0, 1.0, 3.0, 2.0}, 0.5), 2.0);
  EXPECT_EQ(Quantile(std::vector<float>{1.0f, 2.0f}, 0.99), 1.0f);
}

TEST(Quantile, EmptyInputOrQOutsideTheUnitIntervalThrows) {
  EXPECT_THROW(Quantile(std::vector<double>{}, 0.5), std::invalid_argument);
  EXPECT_THROW(Quantile(std::vector<double>{1.0}, -0.1), std::invalid_argument);
  EXPECT_THROW(Quantile(std::vector<double>{1.0}, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace mopad
