// Section and material properties exactly as sections.md defines them.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "stiffmsa/model.hpp"

namespace stiffmsa {

Section Section::circle(double D) {
  Section s;
  s.shape = SectionShape::circle;
  s.D = D;
  return s;
}
Section Section::tube(double D, double t) {
  Section s = circle(D);
  s.shape = SectionShape::tube;
  s.t = t;
  return s;
}
Section Section::rect(double b, double h) {
  Section s;
  s.shape = SectionShape::rect;
  s.b = b;
  s.h = h;
  return s;
}
Section Section::rect_tube(double b, double h, double t) {
  Section s = rect(b, h);
  s.shape = SectionShape::rect_tube;
  s.t = t;
  return s;
}
Section Section::generic(double A, double Iy, double Iz, double J) {
  Section s;
  s.shape = SectionShape::generic;
  s.A = A;
  s.Iy = Iy;
  s.Iz = Iz;
  s.J = J;
  return s;
}

double shear_modulus(const Material& m) {
  if (m.G) return *m.G;
  return m.E / (2.0 * (1.0 + m.nu.value_or(0.0)));
}

SectionProperties section_properties(const Section& s) {
  constexpr double pi = std::numbers::pi;
  SectionProperties p;
  switch (s.shape) {
    case SectionShape::circle: {
      const double D2 = s.D * s.D, D4 = D2 * D2;
      p.A = pi * D2 / 4;
      p.Iy = p.Iz = pi * D4 / 64;
      p.J = pi * D4 / 32;
      p.Asy = p.Asz = 0.9 * p.A;
      break;
    }
    case SectionShape::tube: {
      const double d = s.D - 2 * s.t;
      const double D2 = s.D * s.D, d2 = d * d;
      p.A = pi * (D2 - d2) / 4;
      p.Iy = p.Iz = pi * (D2 * D2 - d2 * d2) / 64;
      p.J = pi * (D2 * D2 - d2 * d2) / 32;
      p.Asy = p.Asz = 0.5 * p.A;
      break;
    }
    case SectionShape::rect: {
      p.A = s.b * s.h;
      p.Iy = s.b * s.h * s.h * s.h / 12;
      p.Iz = s.h * s.b * s.b * s.b / 12;
      const double a = std::max(s.b, s.h), c = std::min(s.b, s.h);
      p.J = a * c * c * c *
            (1.0 / 3.0 - 0.21 * (c / a) * (1 - std::pow(c, 4) / (12 * std::pow(a, 4))));
      p.Asy = p.Asz = 5.0 / 6.0 * p.A;
      break;
    }
    case SectionShape::rect_tube: {
      const double bi = s.b - 2 * s.t, hi = s.h - 2 * s.t;
      p.A = s.b * s.h - bi * hi;
      p.Iy = (s.b * std::pow(s.h, 3) - bi * std::pow(hi, 3)) / 12;
      p.Iz = (s.h * std::pow(s.b, 3) - hi * std::pow(bi, 3)) / 12;
      p.J = 2 * s.t * std::pow(s.b - s.t, 2) * std::pow(s.h - s.t, 2) / (s.b + s.h - 2 * s.t);
      p.Asy = 2 * s.t * s.b;
      p.Asz = 2 * s.t * s.h;
      break;
    }
    case SectionShape::generic:
      p.A = s.A;
      p.Iy = s.Iy;
      p.Iz = s.Iz;
      p.J = s.J;
      break;
  }
  if (s.Asy) p.Asy = s.Asy;
  if (s.Asz) p.Asz = s.Asz;
  return p;
}

}  // namespace stiffmsa
