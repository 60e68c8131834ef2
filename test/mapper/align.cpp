// Metric frame from a reference trajectory: reference readers, WGS84 -> ENU, Umeyama alignment.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/mapper/align.hpp"
#include "test_support.hpp"

namespace {

using hullmap::Error;
using hullmap::test::errorOf;
using namespace hullmap::mapper;
using namespace hullmap::io;

using hullmap::kPi;

Eigen::Matrix3d randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

// A wiggly 3D trajectory (not planar, not collinear), reference poses at the same stamps.
std::vector<ReferencePose> referencePath(std::size_t n) {
  std::vector<ReferencePose> ref(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.1 * static_cast<double>(i);
    ref[i].stamp = 100.0 + 0.5 * static_cast<double>(i);
    ref[i].position = Eigen::Vector3d(3.0 * std::cos(a), 2.0 * std::sin(1.3 * a), 1.0 + 0.3 * std::sin(2.1 * a));
  }
  return ref;
}

// Keyframes = inverse similarity of the reference (what a monocular SLAM run would have written).
std::vector<Keyframe> keyframesFrom(const std::vector<ReferencePose>& ref, const Similarity& truth) {
  std::vector<Keyframe> kf(ref.size());
  for (std::size_t i = 0; i < ref.size(); ++i) {
    kf[i].stamp = ref[i].stamp;
    kf[i].position = truth.rotation.transpose() * (ref[i].position - truth.translation) / truth.scale;
  }
  return kf;
}

TEST(MapperAlign, RecoversARandomSimilarityExactlyFromNoiselessPoses) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int trial = 0; trial < 20; ++trial) {
    Similarity truth;
    truth.scale = std::exp(std::uniform_real_distribution<double>(-3.0, 3.0)(rng));
    truth.rotation = randomRotation(rng);
    truth.translation = Eigen::Vector3d(u(rng), u(rng), u(rng));
    const auto ref = referencePath(40);
    const auto kf = keyframesFrom(ref, truth);
    const Alignment a = alignTrajectory(kf, ref);
    EXPECT_EQ(a.matched, 40u);
    EXPECT_EQ(a.unmatched, 0u);
    EXPECT_NEAR(a.transform.scale, truth.scale, 1e-9 * truth.scale);
    EXPECT_TRUE(a.transform.rotation.isApprox(truth.rotation, 1e-9));
    EXPECT_NEAR(a.transform.rotation.determinant(), 1.0, 1e-12);
    EXPECT_TRUE(a.transform.translation.isApprox(truth.translation, 1e-8));
    EXPECT_LT(a.rmse, 1e-8);

    // Applying it takes keyframes (and points) onto the reference.
    auto moved = kf;
    applySimilarity(a.transform, moved);
    Points pts;
    for (const auto& k : kf) pts.push_back(k.position);
    applySimilarity(a.transform, pts);
    for (std::size_t i = 0; i < ref.size(); ++i) {
      EXPECT_LT((moved[i].position - ref[i].position).norm(), 1e-8);
      EXPECT_LT((pts[i] - ref[i].position).norm(), 1e-8);
    }
  }
}

TEST(MapperAlign, OrientationsAreRotatedWithThePositions) {
  Similarity s;
  s.scale = 2.0;
  s.rotation = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Keyframe> kf(1);
  kf[0].position = Eigen::Vector3d(1, 0, 0);
  applySimilarity(s, kf);
  EXPECT_TRUE(kf[0].position.isApprox(Eigen::Vector3d(0, 2, 0), 1e-12));
  // Camera x axis (was map x) now points along map y.
  EXPECT_TRUE((kf[0].orientation * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST(MapperAlign, NoisyPosesGiveTheNoiseAsRmse) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  Similarity truth;
  truth.scale = 0.37;
  truth.rotation = randomRotation(rng);
  truth.translation = Eigen::Vector3d(1, -2, 0.5);
  auto ref = referencePath(400);
  const auto kf = keyframesFrom(ref, truth);
  for (auto& r : ref) r.position += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const Alignment a = alignTrajectory(kf, ref);
  // 3D Gaussian of 1 cm per axis: RMS distance sqrt(3) cm, minus the 7 fitted degrees of freedom.
  EXPECT_NEAR(a.rmse, 0.01 * std::sqrt(3.0), 0.002);
  EXPECT_GE(a.max_error, a.rmse);
  EXPECT_NEAR(a.transform.scale, truth.scale, 0.01 * truth.scale);
  EXPECT_TRUE(a.transform.rotation.isApprox(truth.rotation, 0.01));
}

TEST(MapperAlign, MatchesStampsWithinTheToleranceAndCountsTheRest) {
  Similarity truth;
  truth.scale = 3.0;
  const auto ref = referencePath(30);
  auto kf = keyframesFrom(ref, truth);
  // Shift stamps: 10 keyframes off by 5 ms (match), 5 off by 1 s (no match), one in nanoseconds.
  for (std::size_t i = 0; i < 10; ++i) kf[i].stamp += 0.005;
  for (std::size_t i = 10; i < 15; ++i) kf[i].stamp += 0.2;
  const Alignment a = alignTrajectory(kf, ref, AlignParams{0.01});
  EXPECT_EQ(a.matched, 25u);
  EXPECT_EQ(a.unmatched, 5u);
  EXPECT_NEAR(a.transform.scale, 3.0, 1e-9);
  const Alignment wide = alignTrajectory(kf, ref, AlignParams{0.3});
  EXPECT_EQ(wide.matched, 30u);
  EXPECT_GT(wide.rmse, 0.0);  // the five moved ones now match their neighbours' positions
}

TEST(MapperAlign, RefusesTooFewMatchesAndDegenerateFits) {
  const auto ref = referencePath(10);
  Similarity truth;
  auto kf = keyframesFrom(ref, truth);
  for (std::size_t i = 2; i < kf.size(); ++i) kf[i].stamp += 100.0;
  std::string msg = errorOf([&] { alignTrajectory(kf, ref); });
  EXPECT_NE(msg.find("align"), std::string::npos) << msg;
  EXPECT_NE(msg.find("2 of 10"), std::string::npos) << msg;
  EXPECT_NE(errorOf([&] { alignTrajectory({}, ref); }).find("align"), std::string::npos);

  // Collinear keyframes: a straight flight determines no rotation about its line.
  std::vector<ReferencePose> line(10);
  std::vector<Keyframe> kline(10);
  for (int i = 0; i < 10; ++i) {
    line[i].stamp = kline[i].stamp = i;
    line[i].position = Eigen::Vector3d(i, 2 * i, 0.5 * i);
    kline[i].position = Eigen::Vector3d(0, 0, 3 * i);
  }
  msg = errorOf([&] { alignTrajectory(kline, line); });
  EXPECT_NE(msg.find("align"), std::string::npos) << msg;
  EXPECT_NE(msg.find("collinear"), std::string::npos) << msg;
  // Coincident: a hovering camera.
  for (auto& k : kline) k.position = Eigen::Vector3d(1, 1, 1);
  for (int i = 0; i < 10; ++i) line[i].position = ref[i].position;
  msg = errorOf([&] { alignTrajectory(kline, line); });
  EXPECT_NE(msg.find("degenerate"), std::string::npos) << msg;
  // A good keyframe set against a collinear reference.
  for (int i = 0; i < 10; ++i) line[i].position = Eigen::Vector3d(i, 2 * i, 0.5 * i);
  auto good = keyframesFrom(ref, truth);
  for (int i = 0; i < 10; ++i) good[i].stamp = line[i].stamp;
  msg = errorOf([&] { alignTrajectory(good, line); });
  EXPECT_NE(msg.find("reference positions"), std::string::npos) << msg;
  EXPECT_NE(errorOf([&] { alignTrajectory(kf, ref, AlignParams{-1.0}); }).find("align"), std::string::npos);
}

TEST(MapperAlign, GeodeticToEcefKnownValues) {
  // WGS84: equatorial radius a = 6378137 m, polar radius b = 6356752.314245 m.
  EXPECT_TRUE(geodeticToEcef(0, 0, 0).isApprox(Eigen::Vector3d(6378137.0, 0, 0), 1e-12));
  EXPECT_LT((geodeticToEcef(0, 90, 0) - Eigen::Vector3d(0, 6378137.0, 0)).norm(), 1e-6);
  EXPECT_LT((geodeticToEcef(90, 0, 0) - Eigen::Vector3d(0, 0, 6356752.314245)).norm(), 1e-5);
  EXPECT_LT((geodeticToEcef(-90, 0, 100) - Eigen::Vector3d(0, 0, -6356852.314245)).norm(), 1e-5);
  EXPECT_LT((geodeticToEcef(0, 180, 10) - Eigen::Vector3d(-6378147.0, 0, 0)).norm(), 1e-6);
}

TEST(MapperAlign, GeodeticToEnuMatchesTheRadiiOfCurvature) {
  // Small steps from an origin: north = (M + h) dlat, east = (N + h) cos(lat) dlon, up = dh, with
  // M = a(1-e2)/(1-e2 sin^2)^1.5 and N = a/sqrt(1-e2 sin^2) (independent of the ECEF route).
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2 - f);
  for (const double lat : {0.0, 47.3769, -33.8688, 80.0}) {
    const Eigen::Vector3d origin(lat, 8.5417, 400.0);
    const double s = std::sin(lat * kPi / 180);
    const double m = a * (1 - e2) / std::pow(1 - e2 * s * s, 1.5);
    const double n = a / std::sqrt(1 - e2 * s * s);
    const double d = 1e-5;  // degrees, about a metre
    const Eigen::Vector3d north = geodeticToEnu(origin + Eigen::Vector3d(d, 0, 0), origin);
    EXPECT_NEAR(north.y(), (m + 400.0) * d * kPi / 180, 1e-4) << lat;
    EXPECT_NEAR(north.x(), 0.0, 1e-6);
    const Eigen::Vector3d east = geodeticToEnu(origin + Eigen::Vector3d(0, d, 0), origin);
    EXPECT_NEAR(east.x(), (n + 400.0) * std::cos(lat * kPi / 180) * d * kPi / 180, 1e-4) << lat;
    EXPECT_NEAR(east.y(), 0.0, 1e-6);
    const Eigen::Vector3d up = geodeticToEnu(origin + Eigen::Vector3d(0, 0, 12.5), origin);
    EXPECT_LT((up - Eigen::Vector3d(0, 0, 12.5)).norm(), 1e-6) << lat;
  }
}

TEST(MapperAlign, ParsesTumAndGpsReferences) {
  const auto tum = parseReferenceTrajectory("# t x y z\n1.0 1 2 3\n1403636579763555840 4 5 6 0 0 0 1\n", "ref.txt",
                                            ReferenceFormat::kTum);
  ASSERT_EQ(tum.size(), 2u);
  EXPECT_EQ(tum[0].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(tum[1].stamp, 1403636579.763555840, 1e-6);

  const auto gps = parseReferenceTrajectory("0 47.0 8.0 500\n1, 47.0, 8.0, 510\n", "gps.txt", ReferenceFormat::kGps);
  ASSERT_EQ(gps.size(), 2u);
  EXPECT_LT(gps[0].position.norm(), 1e-9);  // the first fix is the origin
  EXPECT_LT((gps[1].position - Eigen::Vector3d(0, 0, 10)).norm(), 1e-6);

  std::string msg = errorOf([] { parseReferenceTrajectory("1 2 3\n", "r.txt", ReferenceFormat::kTum); });
  EXPECT_NE(msg.find("r.txt:1"), std::string::npos) << msg;
  msg = errorOf([] { parseReferenceTrajectory("0 1 2 3 0 0 0 1\n", "g.txt", ReferenceFormat::kGps); });
  EXPECT_NE(msg.find("g.txt:1"), std::string::npos) << msg;
  msg = errorOf([] { parseReferenceTrajectory("0 1 x 3\n", "r.txt", ReferenceFormat::kTum); });
  EXPECT_NE(msg.find("'x'"), std::string::npos) << msg;
  msg = errorOf([] { parseReferenceTrajectory("0 1 nan 3\n", "r.txt", ReferenceFormat::kTum); });
  EXPECT_NE(msg.find("non-finite"), std::string::npos) << msg;

  EXPECT_EQ(parseReferenceFormat("GPS"), ReferenceFormat::kGps);
  EXPECT_EQ(parseReferenceFormat(toString(ReferenceFormat::kTum)), ReferenceFormat::kTum);
  try {
    parseReferenceFormat("kml");
    ADD_FAILURE() << "'kml' accepted as a reference format";
  } catch (const Error& e) {
    EXPECT_EQ(e.parameter(), "align_format") << e.what();
    EXPECT_NE(e.detail().find("'kml'"), std::string::npos) << e.what();
  }
}

TEST(MapperAlign, GpsLinesWithoutAFixAreDroppedAndCounted) {
  // As receivers log them: "0 0 0" before the first fix, NaN while it is lost, garbage out of range.
  ReferenceStats stats;
  const auto gps = parseReferenceTrajectory(
      "0 0 0 0\n0.5 nan nan nan\n1 47.0 8.0 500\n1.5 0 0 0\n2, 47.0, 8.0, 510\n3 95 8 500\n4 47 400 500\n"
      "5 47.0 8.0 inf\n",
      "gps.txt", ReferenceFormat::kGps, &stats);
  ASSERT_EQ(gps.size(), 2u);
  EXPECT_EQ(gps[0].stamp, 1.0);
  EXPECT_LT(gps[0].position.norm(), 1e-9);  // the first valid fix is the origin
  EXPECT_LT((gps[1].position - Eigen::Vector3d(0, 0, 10)).norm(), 1e-6);
  const std::map<std::string, std::size_t> want{{"no_fix", 2}, {"non_finite", 2}, {"out_of_range", 2}};
  EXPECT_EQ(stats.dropped, want);
  // Without stats the lines are dropped all the same; a TUM reference still refuses them.
  EXPECT_EQ(parseReferenceTrajectory("0 0 0 0\n1 47 8 500\n", "gps.txt", ReferenceFormat::kGps).size(), 1u);
  const std::string msg = errorOf([] { parseReferenceTrajectory("0 1 nan 3\n", "r.txt", ReferenceFormat::kTum); });
  EXPECT_NE(msg.find("r.txt:1"), std::string::npos) << msg;
}

TEST(MapperAlign, SimilaritiesComposeAndInvert) {
  Similarity a;
  a.scale = 2.5;
  a.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  a.translation = {1, -2, 3};
  Similarity b;
  b.scale = 0.4;
  b.rotation = Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  b.translation = {-4, 0.5, 2};
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.5, -7, 2), Eigen::Vector3d(-3, 4, 9)}) {
    EXPECT_LT((compose(b, a)(p) - b(a(p))).norm(), 1e-12);
    EXPECT_LT((inverse(a)(a(p)) - p).norm(), 1e-12);
    const Eigen::Vector4d h = toMatrix(a) * p.homogeneous();
    EXPECT_LT((h.head<3>() - a(p)).norm(), 1e-12);
    EXPECT_EQ(h[3], 1.0);
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = b.rotation;
  t.translation() = b.translation;
  EXPECT_LT((fromIsometry(t)(Eigen::Vector3d(1, 2, 3)) - t * Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
}

TEST(MapperAlign, GpsReferenceAlignsAMonocularTrajectoryToMetres) {
  // Fixes along a curved climbing path near Zurich; keyframes are a scaled, rotated copy.
  std::string text;
  std::vector<Eigen::Vector3d> geo;
  for (int i = 0; i < 30; ++i) {
    const double a = 0.2 * i;
    geo.emplace_back(47.3769 + 2e-5 * std::sin(a), 8.5417 + 3e-5 * a, 408.0 + 0.5 * i);
    text += std::to_string(10.0 + i) + " " + std::to_string(geo.back()[0]) + " " + std::to_string(geo.back()[1]) + " " +
            std::to_string(geo.back()[2]) + "\n";
  }
  const auto ref = parseReferenceTrajectory(text, "gps.txt", ReferenceFormat::kGps);
  Similarity truth;
  truth.scale = 0.25;
  truth.rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Alignment a = alignTrajectory(keyframesFrom(ref, truth), ref);
  EXPECT_NEAR(a.transform.scale, 0.25, 1e-9);
  EXPECT_LT(a.rmse, 1e-6);
}

// Monocular scale drift, written independently of the build: a street-long path whose map scale
// grows linearly along it (as sim/sample_scene.hpp's model, integrated here in closed form per
// keyframe), the map points placed at fixed offsets from the keyframes in that keyframe's scale.
struct DriftingMap {
  std::vector<ReferencePose> reference;
  std::vector<Keyframe> keyframes;
  Points truth;  // the points, reference frame
  Points map;    // the same points as the drifting map wrote them
};

DriftingMap driftingMap(std::size_t n, double drift, double noise, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  DriftingMap d;
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 0.3, 1.0).normalized()).toRotationMatrix();
  const double base = 0.05;  // map units per metre at the start
  Eigen::Vector3d written = Eigen::Vector3d::Zero(), previous_position = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(n - 1);
    ReferencePose ref;
    ref.stamp = 10.0 + static_cast<double>(i);
    ref.position = Eigen::Vector3d(200.0 * u, 30.0 * std::sin(3.0 * u), 1.5 + 2.0 * u);
    const double scale = base * (1.0 + drift * u);
    if (i > 0) {
      const double previous = base * (1.0 + drift * static_cast<double>(i - 1) / static_cast<double>(n - 1));
      written += 0.5 * (scale + previous) * (r * (ref.position - previous_position));
    }
    previous_position = ref.position;
    d.reference.push_back(ref);
    Keyframe k;
    k.stamp = ref.stamp;
    k.position = written;
    d.keyframes.push_back(k);
    for (int j = 0; j < 20; ++j) {  // points 2-8 m off the path, on both sides and above
      const Eigen::Vector3d offset(gauss(rng), 4.0 * gauss(rng), std::abs(gauss(rng)));
      d.truth.push_back(ref.position + offset);
      d.map.push_back(written + scale * (r * offset));
    }
    Eigen::Vector3d jitter(gauss(rng), gauss(rng), gauss(rng));
    d.reference.back().position += noise * jitter;
  }
  return d;
}

double rmsError(const Points& a, const Points& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(a.size()));
}

TEST(MapperAlignDrift, UndoesMonocularScaleDriftWhereOneSimilarityCannot) {
  for (const double drift : {0.15, 0.3}) {
    DriftingMap d = driftingMap(100, drift, 0.0, 3);
    const Alignment a = alignTrajectory(d.keyframes, d.reference);
    ASSERT_TRUE(a.drift.has_value()) << "drift " << drift;
    EXPECT_GT(a.similarity_rmse, 20.0 * a.rmse);
    EXPECT_LT(a.drift->holdout_rmse, 0.05 * a.similarity_rmse);
    // The oracle: the points' true positions. One similarity leaves metres; the drift model leaves
    // what a linear blend of the local scales cannot follow, centimetres.
    Points similarity = d.map, corrected = d.map;
    applySimilarity(a.transform, similarity);
    applyAlignment(a, corrected);
    const double before = rmsError(similarity, d.truth), after = rmsError(corrected, d.truth);
    EXPECT_GT(before, 0.5) << "drift " << drift;
    EXPECT_LT(after, 0.1) << "drift " << drift;
    // Each local scale is the written one (1 / (0.05 (1 + drift u)) metres per map unit) at its
    // window's centre (one-sided at the path's ends).
    const std::size_t n = d.keyframes.size(), h = a.drift->half_window;
    for (std::size_t i = 0; i < n; ++i) {
      const double centre = 0.5 * static_cast<double>((i >= h ? i - h : 0) + std::min(n - 1, i + h));
      const double written = 1.0 / (0.05 * (1.0 + drift * centre / static_cast<double>(n - 1)));
      EXPECT_NEAR(a.drift->scales[i], written, 0.002 * written) << "drift " << drift << ", anchor " << i;
    }
    // Keyframes move as points do: each lands on its reference.
    std::vector<Keyframe> moved = d.keyframes;
    applyAlignment(a, moved);
    for (std::size_t i = 0; i < moved.size(); ++i)
      EXPECT_LT((moved[i].position - d.reference[i].position).norm(), 0.1) << i;
  }
}

TEST(MapperAlignDrift, WithoutDriftOrWithNoiseAloneOneSimilarityIsKept) {
  // No drift: the similarity is exact and nothing is left to undo.
  const DriftingMap exact = driftingMap(100, 0.0, 0.0, 5);
  const Alignment a = alignTrajectory(exact.keyframes, exact.reference);
  EXPECT_FALSE(a.drift.has_value());
  EXPECT_LT(a.rmse, 1e-6);
  // GPS-like noise of 3 m per axis and no drift: the windows fit noise, which they do not predict.
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const DriftingMap noisy = driftingMap(100, 0.0, 3.0, seed);
    const Alignment b = alignTrajectory(noisy.keyframes, noisy.reference);
    EXPECT_FALSE(b.drift.has_value()) << "seed " << seed << ": similarity RMSE " << b.similarity_rmse;
    EXPECT_DOUBLE_EQ(b.rmse, b.similarity_rmse);
  }
}

TEST(MapperAlignDrift, TheModelCanBeForcedEitherWay) {
  const DriftingMap d = driftingMap(100, 0.3, 0.0, 7);
  AlignParams similarity;
  similarity.model = AlignModel::kSimilarity;
  EXPECT_FALSE(alignTrajectory(d.keyframes, d.reference, similarity).drift.has_value());
  const DriftingMap exact = driftingMap(100, 0.0, 0.0, 7);
  AlignParams drift;
  drift.model = AlignModel::kDrift;
  const Alignment forced = alignTrajectory(exact.keyframes, exact.reference, drift);
  ASSERT_TRUE(forced.drift.has_value());
  for (double s : forced.drift->scales) EXPECT_NEAR(s, forced.transform.scale, 1e-9 * forced.transform.scale);
  // Too few matches for the windows: one similarity, whatever is asked.
  const DriftingMap short_path = driftingMap(kDriftMinAnchors - 1, 0.3, 0.0, 7);
  EXPECT_FALSE(alignTrajectory(short_path.keyframes, short_path.reference, drift).drift.has_value());
  EXPECT_EQ(parseAlignModel("auto"), AlignModel::kAuto);
  EXPECT_EQ(parseAlignModel("drift"), AlignModel::kDrift);
  EXPECT_STREQ(toString(AlignModel::kSimilarity), "similarity");
  try {
    parseAlignModel("piecewise");
    ADD_FAILURE() << "'piecewise' accepted as an align model";
  } catch (const Error& e) {
    EXPECT_EQ(e.parameter(), "align_model") << e.what();
  }
}

TEST(MapperAlignDrift, TheWarpIsExactAtAnchorsAndContinuousAlongThePath) {
  const DriftingMap d = driftingMap(60, 0.3, 0.0, 9);
  const Alignment a = alignTrajectory(d.keyframes, d.reference);
  ASSERT_TRUE(a.drift.has_value());
  const DriftCorrection& c = *a.drift;
  Points anchors = c.anchors;
  applyAlignment(a, anchors);
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    const Eigen::Vector3d expected = c.scales[i] * (a.transform.rotation * c.anchors[i]) + c.translations[i];
    EXPECT_LT((anchors[i] - expected).norm(), 1e-9) << i;
  }
  // Walk the anchor polyline in small steps: the moved walk has no step far longer than the
  // scaled input step (no jump where the nearest segment changes).
  Points walk;
  for (std::size_t i = 0; i + 1 < c.anchors.size(); ++i)
    for (int k = 0; k < 10; ++k) walk.push_back(c.anchors[i] + 0.1 * k * (c.anchors[i + 1] - c.anchors[i]));
  Points moved = walk;
  applyAlignment(a, moved);
  const double largest_scale = *std::max_element(c.scales.begin(), c.scales.end());
  for (std::size_t i = 0; i + 1 < walk.size(); ++i) {
    const double step = (walk[i + 1] - walk[i]).norm();
    EXPECT_LT((moved[i + 1] - moved[i]).norm(), 1.1 * largest_scale * step + 1e-9) << i;
  }
}

// A nearly straight street (0.6 m of sideways wiggle over 200 m), a GPS-like reference of 3 m noise
// per axis, and keyframes written by a random similarity from cameras that look along the street,
// pitched down 10 degrees, without roll (ORB-SLAM's axes: x right, y down, z forward).
struct StraightStreet {
  std::vector<ReferencePose> reference;
  std::vector<Keyframe> keyframes;
  Similarity truth;  // keyframe frame -> metres
};

StraightStreet straightStreet(unsigned seed, double noise) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  StraightStreet s;
  s.truth.scale = 40.0;
  s.truth.rotation = randomRotation(rng);
  s.truth.translation = Eigen::Vector3d(5.0, -3.0, 2.0);
  const Similarity to_map = inverse(s.truth);
  for (int i = 0; i < 100; ++i) {
    const double x = 2.0 * i;
    const Eigen::Vector3d position(x, 0.6 * std::sin(x / 15.0), 1.5 + 0.03 * x);
    const Eigen::Vector3d forward =
        (std::cos(0.17) * Eigen::Vector3d(1.0, 0.04 * std::cos(x / 15.0), 0.03).normalized() -
         std::sin(0.17) * Eigen::Vector3d::UnitZ())
            .normalized();
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
    Eigen::Matrix3d camera;
    camera << right, forward.cross(right), forward;
    Keyframe k;
    k.stamp = 1.0 + i;
    k.position = to_map(position);
    k.orientation = Eigen::Quaterniond(to_map.rotation * camera).normalized();
    s.keyframes.push_back(k);
    ReferencePose r;
    r.stamp = k.stamp;
    r.position = position + noise * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    s.reference.push_back(r);
  }
  return s;
}

double tiltDegrees(const Similarity& fit, const Similarity& truth) {
  const Eigen::Vector3d up = fit.rotation * truth.rotation.transpose() * Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(up.z(), -1.0, 1.0)) * 180.0 / kPi;
}

TEST(MapperAlignRoll, ANearlyStraightNoisyReferenceTakesItsRollFromTheCameras) {
  double worst = 0.0;
  int undetermined = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const StraightStreet s = straightStreet(seed, 3.0);
    const Alignment a = alignTrajectory(s.keyframes, s.reference);
    ASSERT_TRUE(a.roll_from_cameras) << "seed " << seed << ": roll sigma " << a.roll_sigma;
    EXPECT_GT(a.roll_sigma, kPi / 180.0);
    worst = std::max(worst, tiltDegrees(a.transform, s.truth));
    // What the reference alone gives: the least-squares fit, often tens of degrees off.
    undetermined += std::abs(a.roll_turn) > 5.0 * kPi / 180.0 ? 1 : 0;
  }
  // The cameras level the map to what the GPS noise leaves in the pitch along the street.
  EXPECT_LT(worst, 1.0);
  EXPECT_GT(undetermined, 5) << "the reference alone should leave the roll off by > 5 degrees often";
}

TEST(MapperAlignRoll, AReferenceThatPinsTheRollKeepsIt) {
  // The same street without noise: the sideways wiggle pins the roll exactly.
  const StraightStreet exact = straightStreet(3, 0.0);
  const Alignment a = alignTrajectory(exact.keyframes, exact.reference);
  EXPECT_FALSE(a.roll_from_cameras);
  EXPECT_LT(a.roll_sigma, 1e-6);
  EXPECT_LT(tiltDegrees(a.transform, exact.truth), 1e-6);
  // Cameras looking across the path (x axes along it) cannot say where up is about it: kept.
  StraightStreet sideways = straightStreet(4, 3.0);
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (Keyframe& k : sideways.keyframes) k.orientation = Eigen::Quaterniond(k.orientation * quarter).normalized();
  const Alignment b = alignTrajectory(sideways.keyframes, sideways.reference);
  EXPECT_FALSE(b.roll_from_cameras);
  EXPECT_EQ(b.roll_turn, 0.0);
}

}  // namespace
