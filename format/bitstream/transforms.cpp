// Exact, table-driven rotations and scales of the bitstream (spec/README.md,
// "Transform tables"), and the to_string of UvStatus. The tables are literal,
// correctly rounded doubles (generated once with mpmath at 200 bits), so the
// decoder calls no libm function and every platform gets identical values.
#include <cmath>
#include <numbers>

#include "format/bitstream/uvmap.h"

namespace gltfwarp {
namespace {

// kSinQuarter[i] = sin(2*pi*i/256), i = 0..64 (a quarter turn).
constexpr double kSinQuarter[65] = {
    0x0.0p+0,              // sin(2pi*0/256)
    0x1.92155f7a3667ep-6,  // sin(2pi*1/256)
    0x1.91f65f10dd814p-5,  // sin(2pi*2/256)
    0x1.2d52092ce19f6p-4,  // sin(2pi*3/256)
    0x1.917a6bc29b42cp-4,  // sin(2pi*4/256)
    0x1.f564e56a9730ep-4,  // sin(2pi*5/256)
    0x1.2c8106e8e613ap-3,  // sin(2pi*6/256)
    0x1.5e214448b3fc6p-3,  // sin(2pi*7/256)
    0x1.8f8b83c69a60bp-3,  // sin(2pi*8/256)
    0x1.c0b826a7e4f63p-3,  // sin(2pi*9/256)
    0x1.f19f97b215f1bp-3,  // sin(2pi*10/256)
    0x1.111d262b1f677p-2,  // sin(2pi*11/256)
    0x1.294062ed59f06p-2,  // sin(2pi*12/256)
    0x1.4135c94176601p-2,  // sin(2pi*13/256)
    0x1.58f9a75ab1fddp-2,  // sin(2pi*14/256)
    0x1.7088530fa459fp-2,  // sin(2pi*15/256)
    0x1.87de2a6aea963p-2,  // sin(2pi*16/256)
    0x1.9ef7943a8ed8ap-2,  // sin(2pi*17/256)
    0x1.b5d1009e15cc0p-2,  // sin(2pi*18/256)
    0x1.cc66e9931c45ep-2,  // sin(2pi*19/256)
    0x1.e2b5d3806f63bp-2,  // sin(2pi*20/256)
    0x1.f8ba4dbf89abap-2,  // sin(2pi*21/256)
    0x1.073879922ffeep-1,  // sin(2pi*22/256)
    0x1.11eb3541b4b23p-1,  // sin(2pi*23/256)
    0x1.1c73b39ae68c8p-1,  // sin(2pi*24/256)
    0x1.26d054cdd12dfp-1,  // sin(2pi*25/256)
    0x1.30ff7fce17035p-1,  // sin(2pi*26/256)
    0x1.3affa292050b9p-1,  // sin(2pi*27/256)
    0x1.44cf325091dd6p-1,  // sin(2pi*28/256)
    0x1.4e6cabbe3e5e9p-1,  // sin(2pi*29/256)
    0x1.57d69348ceca0p-1,  // sin(2pi*30/256)
    0x1.610b7551d2cdfp-1,  // sin(2pi*31/256)
    0x1.6a09e667f3bcdp-1,  // sin(2pi*32/256)
    0x1.72d0837efff96p-1,  // sin(2pi*33/256)
    0x1.7b5df226aafafp-1,  // sin(2pi*34/256)
    0x1.83b0e0bff976ep-1,  // sin(2pi*35/256)
    0x1.8bc806b151741p-1,  // sin(2pi*36/256)
    0x1.93a22499263fbp-1,  // sin(2pi*37/256)
    0x1.9b3e047f38741p-1,  // sin(2pi*38/256)
    0x1.a29a7a0462782p-1,  // sin(2pi*39/256)
    0x1.a9b66290ea1a3p-1,  // sin(2pi*40/256)
    0x1.b090a58150200p-1,  // sin(2pi*41/256)
    0x1.b728345196e3ep-1,  // sin(2pi*42/256)
    0x1.bd7c0ac6f952ap-1,  // sin(2pi*43/256)
    0x1.c38b2f180bdb1p-1,  // sin(2pi*44/256)
    0x1.c954b213411f5p-1,  // sin(2pi*45/256)
    0x1.ced7af43cc773p-1,  // sin(2pi*46/256)
    0x1.d4134d14dc93ap-1,  // sin(2pi*47/256)
    0x1.d906bcf328d46p-1,  // sin(2pi*48/256)
    0x1.ddb13b6ccc23cp-1,  // sin(2pi*49/256)
    0x1.e212104f686e5p-1,  // sin(2pi*50/256)
    0x1.e6288ec48e112p-1,  // sin(2pi*51/256)
    0x1.e9f4156c62ddap-1,  // sin(2pi*52/256)
    0x1.ed740e7684963p-1,  // sin(2pi*53/256)
    0x1.f0a7efb9230d7p-1,  // sin(2pi*54/256)
    0x1.f38f3ac64e589p-1,  // sin(2pi*55/256)
    0x1.f6297cff75cb0p-1,  // sin(2pi*56/256)
    0x1.f8764fa714ba9p-1,  // sin(2pi*57/256)
    0x1.fa7557f08a517p-1,  // sin(2pi*58/256)
    0x1.fc26470e19fd3p-1,  // sin(2pi*59/256)
    0x1.fd88da3d12526p-1,  // sin(2pi*60/256)
    0x1.fe9cdad01883ap-1,  // sin(2pi*61/256)
    0x1.ff621e3796d7ep-1,  // sin(2pi*62/256)
    0x1.ffd886084cd0dp-1,  // sin(2pi*63/256)
    0x1.0000000000000p+0,  // sin(2pi*64/256)
};

// kScaleFrac[k] = 2^(k/4), k = 0..3.
constexpr double kScaleFrac[4] = {0x1.0000000000000p+0, 0x1.306fe0a31b715p+0, 0x1.6a09e667f3bcdp+0,
                                  0x1.ae89f995ad3adp+0};

}  // namespace

static_assert(kRotationSteps == 256, "the table is for 256 steps");

void rotation_cos_sin(uint32_t code, double& c, double& s) {
  code %= kRotationSteps;
  const uint32_t quadrant = code / 64, r = code % 64;
  const double c0 = kSinQuarter[64 - r], s0 = kSinQuarter[r];
  switch (quadrant) {
    case 0:
      c = c0;
      s = s0;
      break;
    case 1:
      c = -s0;
      s = c0;
      break;
    case 2:
      c = -c0;
      s = -s0;
      break;
    default:
      c = s0;
      s = -c0;
      break;
  }
}

uint32_t rotation_code_for(double radians) {
  if (!std::isfinite(radians)) return 0;
  const double turns = radians / (2.0 * std::numbers::pi);
  const double steps = std::round((turns - std::floor(turns)) * kRotationSteps);
  return static_cast<uint32_t>(static_cast<int64_t>(steps)) % kRotationSteps;
}

double patch_scale(int32_t step) {
  if (step < kMinScaleStep) step = kMinScaleStep;
  if (step > kMaxScaleStep) step = kMaxScaleStep;
  // floor division: step = 4*e + k, k in 0..3; ldexp by an integer is exact.
  const int32_t e = (step >= 0 ? step : step - 3) / 4;
  const int32_t k = step - 4 * e;
  return std::ldexp(kScaleFrac[k], e);
}

int32_t scale_step_for(double factor) {
  if (!(factor > 0) || !std::isfinite(factor)) return 0;
  const double step = std::round(4.0 * std::log2(factor));
  if (step < kMinScaleStep) return kMinScaleStep;
  if (step > kMaxScaleStep) return kMaxScaleStep;
  return static_cast<int32_t>(step);
}

const char* to_string(UvStatus s) {
  switch (s) {
    case UvStatus::ok:
      return "ok";
    case UvStatus::bad_magic:
      return "bad magic (not a GLTFWARP_implicit_texcoords stream)";
    case UvStatus::unsupported_version:
      return "unsupported format version";
    case UvStatus::truncated:
      return "truncated stream";
    case UvStatus::trailing_bytes:
      return "trailing or unused bytes";
    case UvStatus::face_count_mismatch:
      return "face count does not match the mesh";
    case UvStatus::bad_count:
      return "count or size out of range";
    case UvStatus::bad_value:
      return "field value out of range";
    case UvStatus::reserved_bits:
      return "reserved flag bits set";
    case UvStatus::bad_mesh:
      return "mesh index out of range";
    case UvStatus::bad_argument:
      return "invalid argument";
    case UvStatus::layout_bad_patch_id:
      return "layout: bad patch id";
    case UvStatus::layout_patch_order:
      return "layout: patches not ordered by lowest face";
    case UvStatus::layout_unreachable_face:
      return "layout: face unreachable from its patch seed";
    case UvStatus::layout_bad_seed:
      return "layout: seed outside its patch";
    case UvStatus::layout_bad_method:
      return "layout: bad layout method";
    case UvStatus::layout_not_disc:
      return "layout: a solved patch is not a disc";
  }
  return "unknown status";
}

}  // namespace gltfwarp
