/// Colour maps (colormap.hpp). viridis and magma are tabulated at 52 evenly spaced points taken
/// from Matplotlib's 256-entry tables (every fifth entry); linear interpolation between them stays
/// within 1/255 of the full table on every channel.
#include "granular/render/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace granular::render {

namespace {

struct Rgb8 {
  std::uint8_t r, g, b;
};

constexpr std::array<Rgb8, 52> kViridis{{
    {68, 1, 84},    {70, 8, 92},    {71, 16, 99},   {72, 23, 105},  {72, 29, 111},  {72, 36, 117},
    {71, 42, 122},  {70, 48, 126},  {69, 55, 129},  {67, 61, 132},  {65, 66, 135},  {63, 72, 137},
    {61, 78, 138},  {58, 83, 139},  {56, 89, 140},  {53, 94, 141},  {51, 99, 141},  {49, 104, 142},
    {46, 109, 142}, {44, 113, 142}, {42, 118, 142}, {41, 123, 142}, {39, 128, 142}, {37, 132, 142},
    {35, 137, 142}, {33, 142, 141}, {32, 146, 140}, {31, 151, 139}, {30, 156, 137}, {31, 161, 136},
    {33, 165, 133}, {36, 170, 131}, {40, 174, 128}, {46, 179, 124}, {53, 183, 121}, {61, 188, 116},
    {70, 192, 111}, {80, 196, 106}, {90, 200, 100}, {101, 203, 94}, {112, 207, 87}, {124, 210, 80},
    {137, 213, 72}, {149, 216, 64}, {162, 218, 55}, {176, 221, 47}, {189, 223, 38}, {202, 225, 31},
    {216, 226, 25}, {229, 228, 25}, {241, 229, 29}, {253, 231, 37},
}};

constexpr std::array<Rgb8, 52> kMagma{{
    {0, 0, 4},       {2, 2, 11},      {5, 4, 22},      {9, 7, 32},      {14, 11, 43},
    {20, 14, 54},    {26, 16, 66},    {33, 17, 78},    {41, 17, 90},    {49, 17, 101},
    {57, 15, 110},   {66, 15, 117},   {74, 16, 121},   {82, 19, 124},   {90, 22, 126},
    {98, 25, 128},   {106, 28, 129},  {114, 31, 129},  {121, 34, 130},  {129, 37, 129},
    {137, 40, 129},  {145, 43, 129},  {153, 45, 128},  {161, 48, 126},  {170, 51, 125},
    {178, 53, 123},  {186, 56, 120},  {194, 59, 117},  {202, 62, 114},  {210, 66, 111},
    {217, 70, 107},  {224, 76, 103},  {231, 82, 99},   {236, 88, 96},   {241, 96, 93},
    {244, 105, 92},  {247, 114, 92},  {249, 123, 93},  {251, 133, 96},  {252, 142, 100},
    {253, 152, 105}, {254, 161, 110}, {254, 170, 116}, {254, 180, 123}, {254, 189, 130},
    {254, 198, 138}, {254, 207, 146}, {254, 216, 154}, {253, 226, 163}, {253, 235, 172},
    {252, 244, 182}, {252, 253, 191},
}};

std::uint8_t toByte(double v) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
}

double clamp01(double t) {
  return std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
}

template <std::size_t N>
Rgba sampleTable(const std::array<Rgb8, N>& table, double t) {
  const double u = clamp01(t) * double(N - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(u), N - 2);
  const double f = u - double(i);
  const Rgb8 a = table[i], b = table[i + 1];
  return {toByte(a.r + (b.r - a.r) * f), toByte(a.g + (b.g - a.g) * f),
          toByte(a.b + (b.b - a.b) * f), 255};
}

/// Piecewise-linear channel through (position, value) knots; positions ascending from 0 to 1.
double piecewise(double t, std::initializer_list<std::pair<double, double>> knots) {
  auto prev = *knots.begin();
  for (const auto& k : knots) {
    if (t <= k.first) {
      if (k.first <= prev.first) return k.second;
      return prev.second + (k.second - prev.second) * (t - prev.first) / (k.first - prev.first);
    }
    prev = k;
  }
  return prev.second;
}

}  // namespace

Rgba viridis(double t) {
  return sampleTable(kViridis, t);
}

Rgba magma(double t) {
  return sampleTable(kMagma, t);
}

Rgba jet(double t) {
  // Matplotlib's "jet" segment data: dark blue → blue → cyan → yellow → red → dark red.
  t = clamp01(t);
  const double r = piecewise(t, {{0.0, 0.0}, {0.35, 0.0}, {0.66, 1.0}, {0.89, 1.0}, {1.0, 0.5}});
  const double g =
      piecewise(t, {{0.0, 0.0}, {0.125, 0.0}, {0.375, 1.0}, {0.64, 1.0}, {0.91, 0.0}, {1.0, 0.0}});
  const double b = piecewise(t, {{0.0, 0.5}, {0.11, 1.0}, {0.34, 1.0}, {0.65, 0.0}, {1.0, 0.0}});
  return {toByte(255.0 * r), toByte(255.0 * g), toByte(255.0 * b), 255};
}

Rgba grayscale(double t) {
  const std::uint8_t v = toByte(255.0 * clamp01(t));
  return {v, v, v, 255};
}

Rgba categorical(int i) {
  static constexpr std::array<Rgb8, 10> kTab10{{{31, 119, 180},
                                                {255, 127, 14},
                                                {44, 160, 44},
                                                {214, 39, 40},
                                                {148, 103, 189},
                                                {140, 86, 75},
                                                {227, 119, 194},
                                                {127, 127, 127},
                                                {188, 189, 34},
                                                {23, 190, 207}}};
  const Rgb8 c = kTab10[static_cast<std::size_t>(((i % 10) + 10) % 10)];
  return {c.r, c.g, c.b, 255};
}

Rgba mix(Rgba a, Rgba b, double t) {
  t = clamp01(t);
  return {toByte(a.r + (b.r - a.r) * t), toByte(a.g + (b.g - a.g) * t),
          toByte(a.b + (b.b - a.b) * t), toByte(a.a + (b.a - a.a) * t)};
}

Rgba bandColor(ColorMap map, int band, int bandCount) {
  if (bandCount <= 1) return map(0.5);
  return map(double(band) / double(bandCount - 1));
}

double ColorScale::normalize(double value) const {
  if (!(max != min)) return 0.5;
  return clamp01((value - min) / (max - min));
}

Rgba ColorScale::operator()(double value) const {
  if (std::isnan(value)) return {0, 0, 0, 0};
  return map(normalize(value));
}

}  // namespace granular::render
