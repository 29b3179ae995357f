#include "io/colour_difference.hpp"

#include <lcms2.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace heightmarch {
namespace {

// sRGB (floats in [0, 1], encoded) to CIELAB (doubles) under D65. Without Little CMS's one-pixel
// cache its transform may run on several threads at once.
class SrgbToLab {
 public:
  SrgbToLab() {
    const cmsCIExyY d65 = {0.3127, 0.3290, 1.0};
    cmsHPROFILE srgb = cmsCreate_sRGBProfile();
    cmsHPROFILE lab = cmsCreateLab4Profile(&d65);
    if (srgb && lab)
      transform_ = cmsCreateTransform(srgb, TYPE_RGB_FLT, lab, TYPE_Lab_DBL, INTENT_RELATIVE_COLORIMETRIC,
                                      cmsFLAGS_NOCACHE);
    if (srgb) cmsCloseProfile(srgb);
    if (lab) cmsCloseProfile(lab);
    if (!transform_) throw std::runtime_error("Little CMS made no sRGB to CIELAB transform");
  }
  ~SrgbToLab() { cmsDeleteTransform(transform_); }
  SrgbToLab(const SrgbToLab&) = delete;
  SrgbToLab& operator=(const SrgbToLab&) = delete;

  void operator()(const float* srgb, cmsCIELab* lab, std::size_t pixels) const {
    cmsDoTransform(transform_, srgb, lab, cmsUInt32Number(pixels));
  }

 private:
  cmsHTRANSFORM transform_ = nullptr;
};

}  // namespace

std::vector<float> ciede2000(const LinearImage& a, const LinearImage& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
    throw std::logic_error("a colour difference between images of two sizes");
  static const SrgbToLab to_lab;
  const std::size_t w = std::size_t(a.width);
  std::vector<float> delta_e(w * std::size_t(a.height));
  tbb::parallel_for(0, a.height, [&](int y) {
    std::vector<float> encoded(3 * w);
    std::vector<cmsCIELab> lab_a(w), lab_b(w);
    const std::size_t row = std::size_t(y) * w;
    for (const auto& [image, lab] : {std::pair{&a, &lab_a}, std::pair{&b, &lab_b}}) {
      for (std::size_t k = 0; k < 3 * w; ++k) encoded[k] = srgb_encode(image->rgb[3 * row + k]);
      to_lab(encoded.data(), lab->data(), w);
    }
    for (std::size_t x = 0; x < w; ++x)
      delta_e[row + x] = float(cmsCIE2000DeltaE(&lab_a[x], &lab_b[x], 1, 1, 1));
  });
  return delta_e;
}

ImageError summarize_image_error(const std::vector<float>& delta_e,
                                 const std::vector<std::uint8_t>& compared) {
  std::vector<float> values;
  for (std::size_t p = 0; p < delta_e.size(); ++p)
    if (compared[p]) values.push_back(delta_e[p]);
  ImageError e;
  e.pixels = values.size();
  if (values.empty()) return e;
  double sum = 0;
  std::size_t visible = 0;
  for (float d : values) {
    sum += d;
    visible += d > kVisibleDeltaE;
  }
  e.mean = sum / double(values.size());
  e.visible_share = double(visible) / double(values.size());
  const std::size_t rank = std::size_t(std::ceil(0.99 * double(values.size())));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(rank - 1), values.end());
  e.p99 = values[rank - 1];
  return e;
}

}  // namespace heightmarch
