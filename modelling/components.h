#pragma once
// SM5 (paper §3.4, Figure 10, equation (1); method of its ref. [63]): small building service
// components (sockets, switches, signs, extinguishers, radiators, smoke detectors, ...) on the
// walls and ceiling of a room, recognised from the structural elements' (SE) orthoimages with
// the object models the robot carries (interfaces::ObjectModelCatalogue), never placements.
//
// Per SE (SM3 wall, column face or ceiling patch):
//  1. SE orthoimage J^_CD (modelling/orthoimage.h) of the points within `band` of the plane at
//     `pixel` metres, less the points lying on another SE (within surface_band of the floor,
//     the ceiling or a meeting wall: not this SE's protrusions), holes between samples filled by
//     normalised convolution (Gaussian sigma from the local sample spacing, which varies
//     several-fold over one SE; shadows and unseen areas stay unknown, fill_min_weight), the pixels
//     inside the SE's SM4 openings (grown by `opening_margin`) removed; of a candidate region of
//     steps 2-3 touching a removed opening, the part within `casing_cut` of it (and what that cut
//     leaves as slivers or pieces near it) is the opening's casing, the rest a candidate of its
//     own (a sign beside a door, joined to its casing by the scan's blur). It splits into the
//     depth image J^_D (protrusion, m; per pixel its front-most point's: where an oblique scan
//     saw the wall behind an object standing off it, a mean mixed the two) and the colour image
//     J^_C (CIE Lab).
//  2. Geometry path: the high-frequency part of J^_D, i.e. J^_D minus its low-frequency wall
//     surface (the median depth of the surface layer, |depth| < surface_band, in cells of
//     `background_cell`, bilinearly interpolated); unknown pixels in gaps narrower than
//     `gap_close` between protruding ones take their protrusion (the object's own shadow), and
//     so does an unknown area of any size whose rim is protruding pixels alone (inside an
//     object: too few samples there to fill, e.g. between a radiator's fins seen at a slant);
//     pixels protruding more than `protrusion_min` form candidate regions (connected components);
//     each region of a size a catalogue class can have (the filling's sigma there added on each
//     side: the filling spreads a protrusion's edges) is matched by normalised cross-correlation
//     (cv::TM_CCOEFF_NORMED) against that class's depth model, padded with `template_pad` of
//     wall; a peak >= depth_ncc_min is a depth detection (box of the class size at the peak),
//     scored by the NCC times the agreement of the box's measured protrusion with the class's
//     depth (NCC alone cannot tell a 12 mm switch from a 40 mm socket). A detection whose
//     measured protrusion goes on past its box (extend_samples) becomes a longer class of its
//     family (same depth and height, wider; or taller) when that class, placed over it, matches
//     the known pixels at least as well as its own (NCC over the known pixels only, at least
//     masked_known_min of the template known): furniture hid the rest. Each depth detection
//     of a class less deep than wide and tall (its depth model a front face) is then placed at
//     the peak of that known-pixel NCC within search_margin of its own: read as wall, a shadow
//     or a hidden part pulls the plain NCC's peak away from it. A depth detection is
//     dropped when the perceptron reads its box as a component of none of the classes of its
//     size (colour_score_min of the box's best class): its colour contradicts it.
//  3. Colour path: pixels whose Lab distance to the local wall colour (same background
//     estimate as 2, from the colour of the surface layer, each cell taken again from its pixels
//     within colour_delta_e of the median of the cells around it: a flush sign can be most of
//     its cell) exceeds `colour_delta_e`, merged by a dilation of `colour_merge`, are candidate
//     boxes, of any size (a box is where a class's model is searched, not the object: of a
//     built-in socket on a light wall only a pixel or two may differ); a class whose size can
//     hold a box is located by NCC of its colour model (padded with the local wall colour; a
//     flush class also by its model alone, the inner pattern, when that matches better and
//     reaches inner_ncc_min: its outline may not show in the scan; placed by the peak of the
//     model relit by the SE's light, SeLight in components_se_images.cpp) and verified by the
//     perceptron (ComponentRecogniser) on the box of the class size there: a colour
//     detection when the NCC peak is >= colour_ncc_min, the perceptron's best class score
//     beats its "none" score, a class of the same size scores at least colour_score_min of that
//     best (the pattern holds colour statistics and size, not the pictogram), and the
//     box's measured protrusion agrees with the class (depth_consistency, either way). Its
//     score is the
//     best class score (how sure the box is a component); look-alike classes (same size and
//     colours, e.g. signs with different pictograms) are told apart by the NCC in step 5.
//  4. Consensus per class (equation (1)): the Recognition Coherence Matrix R(O) has one row
//     per colour detection and one column per depth detection of class O, each entry
//     alpha = |B_C intersect B_D| / |B_CD| (B_CD the box enclosing both; 0 when apart). The
//     iterated maximum picks the largest entry >= min_pair_alpha, makes it an instance
//     (found_by colour+depth) and removes its row and column, until none is left. A row or
//     column left over is a single-path instance with alpha = 0.5 when its own path is
//     confident (depth score >= single_depth_ncc on at least min_depth_samples measured
//     protruding samples; colour score >= single_colour_score and
//     NCC >= single_colour_ncc, or, for a protruding class, any colour detection whose box
//     protrudes on at least min_depth_samples measured samples as the class does, with wall
//     around it, and differs from the wall's colour over half its area) and
//     does not overlap a paired instance of the class. This replaces the paper's "expected
//     number of instances" (unknown to the robot): the stopping rule is the coherence floor
//     for pairs and the confidence floor for single-path instances.
//  5. Instances of different classes overlapping by more than `max_class_overlap` (of the
//     smaller box) keep the one of larger rank: max(alpha, 0.5) x its evidence (the depth
//     score when depth found it, else the colour NCC).
//  6. On walls, a colour-only instance whose class marks equipment (ObjectModel::marks: a
//     location sign) that was not found below it on the SE takes a look-alike class (same
//     size, detected by the colour path on the same box) whose marked equipment was: signs of
//     one size and colours differ only in pictograms a scan a few metres away does not resolve.
//     And a colour detection of a marking class that step 4 left out (its NCC under
//     single_colour_ncc: a sign seen far off or at a slant) whose marked equipment is an
//     instance below it is supported by it, as a protruding class by its protrusion, and step 4
//     runs again: the equipment is evidence for the sign that marks it.
//  7. Placement on the samples (modelling/sample_fit.h): the instance's box (the depth
//     detection's when depth found it, else the colour detection's) is moved to where its
//     class's model best explains the SE's own points near it, not the filled 5 mm image: a
//     protruding class by its depth model, a flush one by its colour face (relit by the SE's
//     light) on the local wall colour; robust to the object's shadow, which holds no point.
//     Within place_radius; a best place at the edge of that search is no minimum the data
//     show, and the box stays.
// Centre: the placed box's centre on the SE plane (depth 0); map frame.
//
// Robot side only (no truth). Deterministic: ordered loops, OpenCV calls on fixed inputs; the
// perceptron is trained from a CounterRng stream (ComponentTrainingParams). DetectComponents
// runs the SEs in parallel (TBB; the trained recogniser is only read) and gathers them in SE
// order, so the result does not depend on the number of threads.

#include <memory>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/object_model_catalogue.h"
#include "modelling/openings.h"
#include "modelling/orthoimage.h"
#include "modelling/structural_model.h"

namespace mopad::modelling {

struct ComponentParams {
  double pixel = 0.005;          ///< m, SE orthoimage pixel, [0.001, 0.05]
  double band = 0.20;            ///< m, points within +-band of the SE plane, [0.01, 1]
  double fill_sigma = 0.004;     ///< m, least Gaussian sigma of the hole filling, [0.001, 0.1]
  double fill_sigma_max = 0.03;  ///< m, largest Gaussian sigma of the filling, [0.001, 0.2]
  /// Sigma of the filling as a share of the local sample spacing (at least fill_sigma, at
  /// most fill_sigma_max, on a ladder of ratio sqrt 2); it also sizes the closing that keeps
  /// gaps of about a sample spacing filled (0.75 sigma / share), [0.05, 5]
  double fill_spacing_share = 0.6;
  /// m, Gaussian sigma of the window the local sample spacing is measured in, [0.005, 0.5]
  double density_window = 0.04;
  /// A filled pixel is known when its filter weight is at least this share of the local
  /// share of pixels holding points (the weight of a uniform sampling there), [0.001, 1]
  double fill_min_weight = 0.3;
  double opening_margin = 0.05;  ///< m, SM4 openings grown by this before removal, [0, 0.5]
  /// m, a candidate region touching a removed opening loses its pixels within this of the
  /// removal (the opening's casing or trim, beyond opening_margin); the rest is a candidate of
  /// its own. 0 = such a region is dropped whole, [0, 0.5]
  double casing_cut = 0.05;
  double surface_band = 0.015;    ///< m, |depth| of the SE surface layer, [0.001, 0.1]
  double background_cell = 0.4;   ///< m, cell of the low-frequency background, [0.05, 5]
  double protrusion_min = 0.006;  ///< m, high-pass depth of a protruding pixel, [0.001, 0.2]
  /// m, unknown pixels in gaps narrower than this between protruding ones are part of the
  /// protrusion (its own shadow: radiator fins, an extinguisher's side); 0 = off, [0, 0.2]
  double gap_close = 0.03;
  double min_region_area = 4e-4;  ///< m^2, smallest candidate region of the depth path, [0, 1]
  /// Relative tolerance between a candidate's extent and a class's size, [0, 2]
  double size_tolerance = 0.3;
  double size_slack = 0.02;     ///< m, absolute slack added to the size test, [0, 0.5]
  double template_pad = 0.03;   ///< m, wall margin around every model template, [0, 0.5]
  double search_margin = 0.04;  ///< m, NCC search beyond a candidate's box, [0, 0.5]
  double depth_ncc_min = 0.55;  ///< least depth NCC peak of a detection, [-1, 1]
  double colour_delta_e = 8.0;  ///< Lab distance from the wall colour, [1, 200]
  double colour_merge = 0.012;  ///< m, dilation merging colour blobs, [0, 0.2]
  /// Least share of a class's width (height) a colour blob spans to be tried as it, [0, 1]
  double colour_min_extent = 0.2;
  /// Least perceptron score of a colour detection's class, as a share of the box's best class
  /// score, [0, 1]
  double colour_score_min = 0.2;
  double colour_ncc_min = 0.3;  ///< least colour NCC peak of a colour detection, [-1, 1]
  /// Least NCC of a flush class's inner pattern (its colour model without the wall padding)
  /// to stand for the padded match, [-1, 1]
  double inner_ncc_min = 0.75;
  /// The colour model is blurred by this share of the filling's sigma at the candidate before
  /// the NCC (compared with what a scan makes of it); 0 = the sharp model, [0, 3]
  double template_blur_share = 1.0;
  /// A colour detection's class must agree with the box's measured protrusion (high-pass
  /// depth, where known): a protruding class (depth >= 2 protrusion_min) needs its 95th
  /// percentile between this share of its depth and its depth over this share, a flush one
  /// its median below 2 protrusion_min, [0, 1]
  double depth_consistency = 0.3;
  double min_pair_alpha = 0.05;  ///< least alpha of a colour+depth pair, [0, 1]
  /// Least depth score (NCC x protrusion agreement) of a depth-only instance, [-1, 1]
  double single_depth_ncc = 0.5;
  /// Least measured samples protruding > protrusion_min in a depth-only instance's box: with
  /// fewer, its shape is the filling's interpolation of a few (noisy) points, [0, 10000]
  int min_depth_samples = 6;
  double single_colour_score = 0.3;  ///< least score of a colour-only instance, [0, 1]
  double single_colour_ncc = 0.6;    ///< least colour NCC of a colour-only instance, [-1, 1]
  double max_class_overlap = 0.3;    ///< overlap (of the smaller box) across classes, [0, 1]
  /// Least share of a template known for its NCC over the known pixels only, which places
  /// every depth detection (within search_margin of the plain NCC's peak) and makes one whose
  /// measured protrusion goes on past its box a longer class of its family (a four-gang socket
  /// half hidden by a desk, seen as a two-gang one); 0 = neither, [0, 1]
  double masked_known_min = 0.3;
  /// Least measured samples protruding past the box (beyond the filling's blur) for that, [1, 1e4]
  int extend_samples = 3;
  /// Least pixels for the SE's light estimate (SeLight: the scan's colours over the
  /// catalogue's on the front faces of the SE's confident depth detections); with fewer the
  /// colour models keep their catalogue colours; 0 = never relit, [0, 1e6]
  int light_min_pixels = 8;
  /// Pixels of one SE image; a larger SE (a hall's ceiling: 25 m x 15 m is 15 M pixels at
  /// 5 mm) is imaged in overlapping tiles of at most this many, [1, 1e9]
  int max_image_pixels = 8'000'000;
  /// Step 7: each component placed where its model best explains the SE's own samples
  /// (modelling/sample_fit.h); false: at its box on the image
  bool place_on_samples = true;
  /// m, largest move of step 7: beyond the image's placement error (the NCC's search_margin
  /// window, a shadow's pull), [0.001, 0.5]; a best place at its edge is none (no move)
  double place_radius = 0.06;
  /// Edge uncertainty of step 7 as a share of the local sample spacing (1 / sqrt 12: an edge
  /// anywhere between two samples), [0, 2]
  double place_edge_share = 0.2887;
  /// Scale of step 7's Cauchy loss in robust sigmas of the noise measured on the wall around
  /// the component (2.385: 95 % efficiency at Gaussian noise), [0.5, 20]
  double place_cauchy_k = 2.385;

  template <class V>
  void Visit(V& v) {
    v("pixel", pixel, Bounds{0.001, 0.05});
    v("band", band, Bounds{0.01, 1.0});
    v("fill_sigma", fill_sigma, Bounds{0.001, 0.1});
    v("fill_sigma_max", fill_sigma_max, Bounds{0.001, 0.2});
    v("fill_spacing_share", fill_spacing_share, Bounds{0.05, 5.0});
    v("density_window", density_window, Bounds{0.005, 0.5});
    v("fill_min_weight", fill_min_weight, Bounds{0.001, 1.0});
    v("opening_margin", opening_margin, Bounds{0.0, 0.5});
    v("casing_cut", casing_cut, Bounds{0.0, 0.5});
    v("surface_band", surface_band, Bounds{0.001, 0.1});
    v("background_cell", background_cell, Bounds{0.05, 5.0});
    v("protrusion_min", protrusion_min, Bounds{0.001, 0.2});
    v("gap_close", gap_close, Bounds{0.0, 0.2});
    v("min_region_area", min_region_area, Bounds{0.0, 1.0});
    v("size_tolerance", size_tolerance, Bounds{0.0, 2.0});
    v("size_slack", size_slack, Bounds{0.0, 0.5});
    v("template_pad", template_pad, Bounds{0.0, 0.5});
    v("search_margin", search_margin, Bounds{0.0, 0.5});
    v("depth_ncc_min", depth_ncc_min, Bounds{-1.0, 1.0});
    v("colour_delta_e", colour_delta_e, Bounds{1.0, 200.0});
    v("colour_merge", colour_merge, Bounds{0.0, 0.2});
    v("colour_min_extent", colour_min_extent, Bounds{0.0, 1.0});
    v("colour_score_min", colour_score_min, Bounds{0.0, 1.0});
    v("colour_ncc_min", colour_ncc_min, Bounds{-1.0, 1.0});
    v("inner_ncc_min", inner_ncc_min, Bounds{-1.0, 1.0});
    v("template_blur_share", template_blur_share, Bounds{0.0, 3.0});
    v("depth_consistency", depth_consistency, Bounds{0.0, 1.0});
    v("min_pair_alpha", min_pair_alpha, Bounds{0.0, 1.0});
    v("single_depth_ncc", single_depth_ncc, Bounds{-1.0, 1.0});
    v("min_depth_samples", min_depth_samples, Bounds{0, 10000});
    v("single_colour_score", single_colour_score, Bounds{0.0, 1.0});
    v("single_colour_ncc", single_colour_ncc, Bounds{-1.0, 1.0});
    v("max_class_overlap", max_class_overlap, Bounds{0.0, 1.0});
    v("masked_known_min", masked_known_min, Bounds{0.0, 1.0});
    v("light_min_pixels", light_min_pixels, Bounds{0, 1000000});
    v("extend_samples", extend_samples, Bounds{1, 10000});
    v("max_image_pixels", max_image_pixels, Bounds{1, 1e9});
    v("place_on_samples", place_on_samples);
    v("place_radius", place_radius, Bounds{0.001, 0.5});
    v("place_edge_share", place_edge_share, Bounds{0.0, 2.0});
    v("place_cauchy_k", place_cauchy_k, Bounds{0.5, 20.0});
  }
  void Validate() const;  ///< InputError naming the field
};

/// How the perceptron of the colour path learns from the catalogue alone: every class image
/// resampled at pixel sizes in [pixel_min, pixel_max] (scan densities and incidence: the two
/// axes scaled independently by up to `stretch`), blurred (Gaussian sigma up to blur_max
/// pixels, as from several scan positions), shifted by up to a pixel, with colour gain and
/// offset changes (up to colour_gain, colour_offset) and per-pixel noise; negatives (label
/// "none") are plain wall, stains (blobs of any colour) and picture crops (random coloured
/// rectangles) at the classes' sizes.
struct ComponentTrainingParams {
  int samples_per_class = 100;  ///< augmented samples of each class and of "none" x3, [1, 1e5]
  int hidden = 32;              ///< neurons of the hidden layer, [2, 1000]
  int iterations = 300;         ///< RPROP iterations, [1, 1e6]
  double pixel_min = 0.004;     ///< m, [0.001, 0.1]
  double pixel_max = 0.012;     ///< m, [pixel_min, 0.1]
  double stretch = 0.15;        ///< relative, [0, 0.9]
  double blur_max = 1.2;        ///< pixels, [0, 10]
  double colour_gain = 0.2;     ///< relative, [0, 1]
  double colour_offset = 12.0;  ///< 0-255 units, [0, 128]
  double noise = 6.0;           ///< 0-255 units, 1 sigma, [0, 64]
  std::uint64_t seed = 1;       ///< augmentation stream and network initialisation
  /// Adds the L (lightness) channel of Lab, reduced like S, a and b, to the paper's 12-value
  /// pattern (16 values + the box size); false keeps the paper's S, a, b only
  bool lightness = true;

  template <class V>
  void Visit(V& v) {
    v("samples_per_class", samples_per_class, Bounds{1, 100000});
    v("lightness", lightness);
    v("hidden", hidden, Bounds{2, 1000});
    v("iterations", iterations, Bounds{1, 1000000});
    v("pixel_min", pixel_min, Bounds{0.001, 0.1});
    v("pixel_max", pixel_max, Bounds{0.001, 0.1});
    v("stretch", stretch, Bounds{0.0, 0.9});
    v("blur_max", blur_max, Bounds{0.0, 10.0});
    v("colour_gain", colour_gain, Bounds{0.0, 1.0});
    v("colour_offset", colour_offset, Bounds{0.0, 128.0});
    v("noise", noise, Bounds{0.0, 64.0});
    v("seed", seed);
  }
  void Validate() const;  ///< InputError naming the field
};

/// The colour path's classifier (the paper's perceptron, OpenCV ml::ANN_MLP: one hidden layer,
/// symmetric sigmoid, on-line back-propagation) and the catalogue it was trained on. Features: the
/// paper's S, a, b pattern, by default with the same for L (ComponentTrainingParams::lightness),
/// and the box size. Classes that look alike (LookAlikeGroups, e.g. a flush and a surface socket)
/// share an output; the geometry tells them apart. Input: a colour box (RGB, top row first) and its
/// size in metres; output: a score in [0, 1] per catalogue class (Classes() order) and for "none"
/// (last). Const methods are thread-safe.
class ComponentRecogniser {
 public:
  ComponentRecogniser();
  ~ComponentRecogniser();
  ComponentRecogniser(const ComponentRecogniser&) = delete;
  ComponentRecogniser& operator=(const ComponentRecogniser&) = delete;
  ComponentRecogniser(ComponentRecogniser&&) noexcept;
  ComponentRecogniser& operator=(ComponentRecogniser&&) noexcept;

  /// Trains on the catalogue's images (see ComponentTrainingParams). InputError for an empty
  /// catalogue, a model without images or bad params.
  static ComponentRecogniser Train(const interfaces::ObjectModelCatalogue& catalogue,
                                   const ComponentTrainingParams& params = {});
  /// Writes the network (OpenCV FileStorage YAML) with the class list; InputError on failure.
  void Save(const std::string& path) const;
  /// Reads what Save wrote; InputError when the file is malformed or its classes differ from
  /// the catalogue's.
  static ComponentRecogniser Load(const interfaces::ObjectModelCatalogue& catalogue,
                                  const std::string& path);

  bool Trained() const;
  const interfaces::ObjectModelCatalogue& Catalogue() const;
  /// Scores of a box of `width` x `height` pixels (RGB bytes, top row first) spanning
  /// width_m x height_m metres: Classes().size() + 1 values, the last "none".
  std::vector<float> Score(const std::vector<std::uint8_t>& rgb, int width, int height,
                           double width_m, double height_m) const;
  /// Share of held-out augmented samples (a second stream) classified right (the right
  /// look-alike group), [0, 1].
  double Accuracy(int samples_per_class, std::uint64_t seed) const;
  /// The same per class (Classes() order, then "none").
  std::vector<double> ClassAccuracy(int samples_per_class, std::uint64_t seed) const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

enum class FoundBy : std::uint8_t { kColourAndDepth = 0, kColour = 1, kDepth = 2 };
const char* ToString(FoundBy f);  ///< "colour+depth", "colour", "depth"

/// One recognised component (SM5).
struct DetectedComponent {
  std::string id;               ///< "bsc_1", ... (per room, in SE order then u, v)
  std::string class_name;       ///< catalogue class
  std::string host;             ///< SM3 patch id
  Vec3 centre = Vec3::Zero();   ///< map frame, on the host plane
  Vec3 normal = Vec3::UnitX();  ///< unit, the host's normal into the room
  Vec3 size = Vec3::Zero();     ///< m, the class's width, height, depth
  double alpha = 0.0;           ///< recognition coherence level, [0, 1]
  FoundBy found_by = FoundBy::kColourAndDepth;
  double u = 0.0, v = 0.0;    ///< m, centre in the host's PatchFrame
  double depth_score = 0.0;   ///< depth NCC peak (0 without a depth detection)
  double colour_score = 0.0;  ///< perceptron score (0 without a colour detection)
};

struct Sm5Model {
  std::string room;
  std::vector<DetectedComponent> components;
};

/// One path's detection of one class on one SE: a box in image pixels and its score.
struct PathDetection {
  int class_index = 0;
  double col0 = 0, row0 = 0, col1 = 0, row1 = 0;  ///< pixel box [col0, col1) x [row0, row1)
  /// depth: NCC peak x (measured / model protrusion, the smaller over the larger); colour: the
  /// box's best perceptron score; [0, 1]
  double score = 0.0;
  double ncc = 0.0;  ///< NCC peak of the path's model template, [-1, 1]
  /// depth: measured samples (pixels holding points) in the box protruding > protrusion_min;
  /// colour: the same where the box's protrusion supports a protruding class (else 0)
  int samples = 0;
  /// colour, of a class that marks equipment (ObjectModel::marks): that equipment was found
  /// below it on the SE (step 6), which supports it as protruding samples support a
  /// protruding class
  bool marked = false;
};

/// Equation (1): area of the boxes' intersection over the area of the box enclosing both; 0
/// when they do not overlap.
double CoherenceAlpha(const PathDetection& colour, const PathDetection& depth);

/// Steps 4-5 on the detections of one SE: instances with alpha, path and the box (index into
/// the inputs: -1 when that path did not find it).
struct ConsensusInstance {
  int class_index = 0;
  int colour = -1, depth = -1;
  double alpha = 0.5;
};
std::vector<ConsensusInstance> Consensus(const std::vector<PathDetection>& colour,
                                         const std::vector<PathDetection>& depth,
                                         const ComponentParams& params);

/// The components of one SE from its orthoimage (built at params.pixel, see BuildOrthoimage),
/// the SE's openings (their u, v rectangles) and whether it is a ceiling (the model's height
/// axis runs along world y there). `samples`: the points the image was built from (map frame);
/// with them (and params.place_on_samples) each component is placed on them (step 7), without
/// them on the image. Ids are left empty.
std::vector<DetectedComponent> DetectSeComponents(const Orthoimage& image, const std::string& host,
                                                  bool ceiling,
                                                  const std::vector<DetectedOpening>& openings,
                                                  const ComponentRecogniser& recogniser,
                                                  const ComponentParams& params,
                                                  const OrthoPoints* samples = nullptr);

/// Step 1's points of patch `se` of `sm3` (indices into `points`, ascending): those within
/// `band` of its plane over its extent, less those lying on another patch (within
/// surface_band of its plane, over its extent grown by `band`). Where a wall meets the floor,
/// the ceiling or the next wall, that patch's surface runs through this one's band and reads as
/// a protruding strip along its edge. InputError when `se` is out of range.
std::vector<std::size_t> SePointIndices(const StructuralModel& sm3, std::size_t se,
                                        const std::vector<Eigen::Vector3f>& points,
                                        const ComponentParams& params);

/// SM5 of one room: every wall, column face and ceiling patch of `sm3` imaged and searched,
/// SM4's openings removed. InputError for bad params, point arrays or an untrained recogniser.
Sm5Model DetectComponents(const StructuralModel& sm3, const Sm4Model& sm4,
                          const OrthoPoints& points, const ComponentRecogniser& recogniser,
                          const ComponentParams& params);

}  // namespace mopad::modelling
