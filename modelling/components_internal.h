#pragma once
// Internal to SM5 (modelling/components.h; components*.cpp): the SE images the steps share and
// the steps and box measures that more than one of those files call.

#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "modelling/components.h"
#include "modelling/sample_fit.h"

namespace mopad::modelling::detail {

// The SE images of steps 1-3, all rows x cols of the orthoimage.
struct SeImages {
  cv::Mat valid;     // CV_8U, 255 = known and outside the openings
  cv::Mat depth;     // CV_32F, m, filled J^_D
  cv::Mat rgb;       // CV_8UC3, filled J^_C (RGB)
  cv::Mat lab;       // CV_32FC3, J^_C in CIE Lab
  cv::Mat highpass;  // CV_32F, m, depth minus its wall background (0 where not valid)
  cv::Mat wall_rgb;  // CV_8UC3, local wall colour
  cv::Mat delta_e;   // CV_32F, Lab distance to the local wall colour (0 where not valid)
  cv::Mat blur;      // CV_32F, pixels, sigma of the filling at each pixel (0 where unseen)
  cv::Mat spacing;   // CV_32F, m, local sample spacing (pixel / sqrt(points per pixel); 0 unseen)
  cv::Mat measured;  // CV_8U, 255 = the pixel holds points (not filled)
  std::vector<cv::Rect> openings;  // the removed openings (grown by opening_margin), pixels
};

// Step 1: normalised convolution of the imaged pixels, openings removed, at the LOCAL sample
// spacing. One SE is sampled very unevenly (a wall 1 m from a scan and 8 m from it, the band
// near the floor at grazing incidence): a filter sized by the SE's typical spacing leaves the
// sparse parts full of holes, which splits a component into fragments. So the spacing is
// measured per pixel (points per pixel over the seen area in a Gaussian window of
// `density_window`), each pixel is filled at the smallest of a ladder of sigmas (ratio sqrt 2)
// reaching fill_spacing_share of its spacing, and its weight is compared with the local share
// of pixels holding points (the weight a uniform sampling gives there).
void FillSe(const Orthoimage& im, const std::vector<DetectedOpening>& openings,
            const ComponentParams& p, SeImages& se);

// Steps 2-3: the low-frequency wall surface (depth and colour medians of the surface layer per
// background cell, bilinear), the depth high-pass and the colour distance.
void Background(const ComponentParams& p, double pixel, SeImages& se);

// A candidate region that touches a removed opening (within 2 pixels) is the rest of the
// opening's casing or trim beyond the removal margin (a door casing is often wider than the
// margin, and SM4's edges are known to a centimetre or two), not a component on the wall.
bool TouchesOpening(const SeImages& se, const cv::Rect& r);

// The casing is cut off, not the region with it: in a candidate mask (connected after a
// dilation of `grow` pixels, as Regions joins it), a region touching a removed opening loses
// its pixels within casing_cut of that opening, and what stays apart from it (a sign or a
// switch beside a door, joined to the casing by the scan's blur) is a candidate of its own.
// Regions that touch no opening are left as they are.
void CutCasings(const SeImages& se, const ComponentParams& p, double pixel, int grow,
                cv::Mat& mask);

// Candidate boxes: connected components of `mask` (CV_8U), as [c0, r0, c1, r1) pixel boxes.
std::vector<cv::Rect> Regions(const cv::Mat& mask, int grow);

// The light the SE's colours were measured in, as a factor of the light of the catalogue's
// colour images (linear RGB): the median ratio of measured to model colour over the measured
// pixels of the front faces of the SE's confident depth detections (depth-only instance
// floors: score and measured samples; FrontFaceModel classes), inside their boxes by the
// filling's blur + 1 pixel and away from the model's own colour edges (its 3 x 3 neighbourhood
// within 8 levels per channel), where the model is not dark (mean linear >= 0.1: a ratio of
// small numbers).
// 1 (the catalogue's colours as they are) with fewer than light_min_pixels. The composite
// template puts a model beside the wall colour the scan measured: in the scanner's light (0.6
// of full on the vertical faces of the default scenes) a white socket on a white wall shows
// no outline, while the unlit model's plate stood out and its NCC sat on the socket's lit top
// edge, 5 cm high.
double SeLight(const SeImages& se, const std::vector<PathDetection>& depth, bool ceiling,
               const interfaces::ObjectModelCatalogue& cat, const ComponentParams& p);

bool MountsOn(const interfaces::ObjectModel& m, bool ceiling);

// The class's box can be the candidate: extent within tolerance (colour blobs may be smaller:
// a part of the model differs from the wall), plus `spread` metres on each side.
bool SizeFits(const cv::Rect& r, double pixel, const interfaces::ObjectModel& m,
              const ComponentParams& p, double min_share, double spread = 0.0);

// A template match: its score and the template's centre in unpadded pixel coordinates.
struct Peak {
  double score = -2.0;
  double col = 0.0, row = 0.0;
};

// NCC of `templ` over the window around `r` in `image` (both padded by `pad` pixels of
// `image_padded`): best score and the template's centre in unpadded pixel coordinates.
Peak MatchAround(const cv::Mat& image_padded, int pad, const cv::Mat& templ, const cv::Rect& r,
                 int margin);

// NCC of `templ` over the KNOWN pixels only (`known_padded` nonzero), with the template centred
// at every place in `centres` (unpadded pixels: the template's centre pixel ranges over it);
// places where less than `min_known` of the template is known score -2. From six plain
// correlations: with M the mask, I the image and T the template, the sums over the known
// pixels n = M*1, sI = MI*1, sII = MI^2*1, sT = M*T, sTT = M*T^2, sIT = MI*T give
// (sIT - sI sT / n) / sqrt((sII - sI^2 / n)(sTT - sT^2 / n)).
Peak MaskedMatch(const cv::Mat& image_padded, const cv::Mat& known_padded, int pad,
                 const cv::Mat& templ, const cv::Rect& centres, double min_known);

PathDetection BoxAt(int k, const interfaces::ObjectModel& m, double pixel, const Peak& pk);

double OverlapOfSmaller(const PathDetection& a, const PathDetection& b);

// Keeps the best of same-class detections that overlap by more than half (several candidate
// regions of one object reach the same peak).
void Dedupe(std::vector<PathDetection>& d);

cv::Mat MaybeFlip(cv::Mat m, bool ceiling);

// A detection's box in whole pixels, clipped to the SE image.
cv::Rect BoxRect(const SeImages& se, const PathDetection& d);

// Measured protrusion of a box: the `quantile` of the high-pass depth over its known pixels (m);
// NaN when less than 30 % of the box is known.
double BoxProtrusion(const SeImages& se, const PathDetection& d, double quantile = 0.95);

// Measured samples (pixels holding points, not filled) in `box` (within the image)
// protruding more than protrusion_min.
int ProtrudingSamplesIn(const SeImages& se, const cv::Rect& box, const ComponentParams& p);

// The same in a detection's box.
int ProtrudingSamples(const SeImages& se, const PathDetection& d, const ComponentParams& p);

// The measured protrusion inside a box agrees with the class (ComponentParams::
// depth_consistency); true when too little of the box is known to tell.
bool DepthAgrees(const SeImages& se, const PathDetection& d, const interfaces::ObjectModel& m,
                 const ComponentParams& p);

// Support from the geometry for a colour-only instance (step 4) of a protruding class: the
// measured samples of the box protruding more than protrusion_min, when the box's protrusion
// is known (DepthAgrees has checked it against the class's depth), is the object's own, not
// part of a larger one (a radiator, a box it is painted on: under a fifth of the measured ring
// of template_pad around the box protrudes; the ring begins two filling sigmas out, past the
// spread of the object's own edges, which reach 2 sigma for a 19 cm deep extinguisher), and
// at least half of the box differs from the wall's colour (colour_delta_e: the object's colour
// is evidence, not only its pattern); else 0.
int SupportingSamples(const SeImages& se, const PathDetection& d, const interfaces::ObjectModel& m,
                      double pixel, const ComponentParams& p);

// The class's depth model (a height map of its front face) is what an oblique scan sees of
// it: it stands off the wall less than it is wide and tall. An object deeper than that (a
// fire extinguisher) is seen mostly by its sides, whose front-most points fall across and
// beyond its outline.
bool FrontFaceModel(const interfaces::ObjectModel& m);

// Two classes of one mounting whose widths and heights agree within 10 %.
bool SameSize(const interfaces::ObjectModel& a, const interfaces::ObjectModel& b);

// The colour box of class m centred at (col, row): RGB bytes in the model's orientation.
std::vector<std::uint8_t> ColourBox(const cv::Mat& rgb_padded, int pad, const PathDetection& d,
                                    bool ceiling, int* w, int* h);

// Step 2 on one SE.
std::vector<PathDetection> DepthPath(const SeImages& se, double pixel, bool ceiling,
                                     const interfaces::ObjectModelCatalogue& cat,
                                     const ComponentParams& p);

// A depth detection whose colour contradicts its class: the perceptron reads the box as a
// component (its best class beats "none") but no class of this one's size among its likely
// ones (colour_score_min of the best), e.g. a white socket's box taken by depth for a red
// fire alarm switch of nearly its shape. A box the perceptron reads as plain wall (a
// radiator of the wall's colour) does not contradict.
bool ColourContradicts(const SeImages& se, double pixel, bool ceiling, const PathDetection& d,
                       const ComponentRecogniser& rec, const ComponentParams& p);

// Step 3 on one SE.
std::vector<PathDetection> ColourPath(const SeImages& se, double pixel, bool ceiling, double light,
                                      const ComponentRecogniser& rec, const ComponentParams& p);

// The points an SE image was built from (map frame) as samples in its pixels
// (modelling/sample_fit.h).
SeSamples SeSamplesOf(const Orthoimage& image, const OrthoPoints& points);

// Step 7: an instance's box moved to where its class's model best explains the SE's samples
// (FitOnSamples): a protruding class by its depth model (its height map), a flush one by its
// colour face, relit by the SE's light (SeLight), on the local wall colour.
void PlaceOnSamples(const SeSamples& samples, const SeImages& se, const interfaces::ObjectModel& m,
                    bool ceiling, double pixel, double light, const ComponentParams& p,
                    PathDetection& b);

// The box that places an instance: its depth detection's when depth found it, else its
// colour detection's.
const PathDetection& InstanceBox(const ConsensusInstance& c,
                                 const std::vector<PathDetection>& colour,
                                 const std::vector<PathDetection>& depth);

// Step 6's support: flags the colour detections of marking classes left out of `instances`
// whose marked equipment is an instance below them; true when it flagged any.
bool MarkSupport(const std::vector<PathDetection>& depth,
                 const interfaces::ObjectModelCatalogue& cat,
                 const std::vector<ConsensusInstance>& instances,
                 std::vector<PathDetection>& colour);

// Location signs of one size and colours differ only in their pictograms, which a scan a few
// metres away does not resolve (the colour NCCs of the look-alike classes then differ by
// chance). What a sign marks does: a colour-only instance whose class marks no equipment found
// below it on this SE (overlapping it along u) takes a look-alike class, detected on the same
// box by the colour path, whose marked equipment is there (interfaces::ObjectModel::marks: the
// catalogue's relation, a robot's knowledge of the objects, not of the scene).
void ApplyMarks(const std::vector<PathDetection>& colour, const std::vector<PathDetection>& depth,
                const interfaces::ObjectModelCatalogue& cat,
                std::vector<ConsensusInstance>& instances);

}  // namespace mopad::modelling::detail
