#include "geometry/rigid3.h"

#include <gtest/gtest.h>

#include <random>

#include "geometry/rigid3_matrix.h"

namespace ripple::geometry {
namespace {

Rigid3d RandomPose(std::mt19937* rng) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector3d aa(n(*rng), n(*rng), n(*rng));
  return Rigid3d::FromAxisAngle(aa, Eigen::Vector3d(n(*rng), n(*rng), n(*rng)));
}

TEST(Rigid3Test, ComposesAndInverts) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 50; ++trial) {
    const Rigid3d a_from_b = RandomPose(&rng), b_from_c = RandomPose(&rng);
    const Eigen::Vector3d p_in_c(0.1, -0.2, 0.3);
    const Eigen::Vector3d p_in_a = (a_from_b * b_from_c) * p_in_c;
    EXPECT_LT((p_in_a - a_from_b * (b_from_c * p_in_c)).norm(), 1e-12);
    const Rigid3d identity = a_from_b * a_from_b.Inverse();
    EXPECT_LT(RotationDistance(identity, Rigid3d::Identity()), 1e-7);
    EXPECT_LT(TranslationDistance(identity, Rigid3d::Identity()), 1e-12);
    EXPECT_GE(a_from_b.CanonicalRotation().w(), 0.0);
    const Eigen::Matrix4d m = a_from_b.Matrix();
    EXPECT_LT((m.topLeftCorner<3, 3>() * p_in_c + m.topRightCorner<3, 1>() -
               a_from_b * p_in_c)
                  .norm(),
              1e-12);
  }
}

TEST(Rigid3Test, MatrixFormAgrees) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const Rigid3d a_from_b = RandomPose(&rng), b_from_c = RandomPose(&rng);
    const Rigid3dMatrix m = ToMatrixForm(a_from_b);
    const Eigen::Vector3d p(0.3, 0.1, -0.4);
    const std::array<double, 3> q = m.Apply({p.x(), p.y(), p.z()});
    const Eigen::Vector3d expected = a_from_b * p;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(q[i], expected[i], 1e-12);
    // Composition and inverse commute with the conversion.
    const Rigid3dMatrix ac = m * ToMatrixForm(b_from_c);
    const Rigid3d back = FromMatrixForm(ac);
    EXPECT_LT(RotationDistance(back, a_from_b * b_from_c), 1e-7);
    EXPECT_LT(TranslationDistance(back, a_from_b * b_from_c), 1e-12);
    const Rigid3d inv = FromMatrixForm(m.Inverse());
    EXPECT_LT(RotationDistance(inv, a_from_b.Inverse()), 1e-7);
    EXPECT_LT(TranslationDistance(inv, a_from_b.Inverse()), 1e-12);
    EXPECT_TRUE(m.IsFinite());
  }
}

TEST(Rigid3MatrixTest, FromQuaternionNormalises) {
  const Rigid3dMatrix m =
      Rigid3dMatrix::FromQuaternion(2, 0, 0, 2, {1, 2, 3});  // 90 deg about z
  const std::array<double, 3> p = m.Apply({1, 0, 0});
  EXPECT_NEAR(p[0], 1, 1e-15);
  EXPECT_NEAR(p[1], 3, 1e-15);
  EXPECT_NEAR(p[2], 3, 1e-15);
  EXPECT_EQ(Rigid3dMatrix::FromQuaternion(0, 0, 0, 0, {0, 0, 0}),
            Rigid3dMatrix::Identity());
  Rigid3dMatrix bad = Rigid3dMatrix::FromTranslation(1, 2, 3);
  EXPECT_TRUE(bad.IsFinite());
  bad.rotation[4] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(bad.IsFinite());
  EXPECT_NE(bad, Rigid3dMatrix::Identity());
}

// Templated on the scalar: float (and so Ceres Jets) flow through.
TEST(Rigid3Test, OtherScalars) {
  const Rigid3<float> f = Rigid3d::FromAxisAngle(Eigen::Vector3d(0, 0, 0.5),
                                                 Eigen::Vector3d(1, 0, 0))
                              .Cast<float>();
  const Eigen::Vector3f p = f * Eigen::Vector3f(1, 0, 0);
  EXPECT_NEAR(p.x(), 1 + std::cos(0.5f), 1e-6);
  const Rigid3Matrix<float> m = ToMatrixForm(f);
  EXPECT_NEAR(m.Apply({1, 0, 0})[1], std::sin(0.5f), 1e-6);
}

}  // namespace
}  // namespace ripple::geometry
