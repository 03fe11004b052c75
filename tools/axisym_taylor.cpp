// axisym_taylor: an independent 2D axisymmetric explicit Lagrangian code for the Taylor
// impact of a bar on a rigid frictionless anvil. It shares no code with core/ on purpose: it
// is the cross-check of the 3D code's Taylor result. Standard library only, SI units.
//
// Method (textbook): 4-node quads in (r, z), volume-weighted (Galerkin) axisymmetric forces
// with the hoop term, mean dilatation from the exact ring volume, and either one-point
// (centroid) integration with Flanagan-Belytschko viscous hourglass control (--element q1,
// default) or 2x2 Gauss integration of the deviatoric part (--element sri, selective-reduced:
// no hourglass modes, the cross-check of the hourglass control); quadratic + linear bulk
// viscosity, hypoelastic Jaumann-rate deviatoric stress with a radial return on the
// Johnson-Cook flow stress, linear EOS p = K (V0/V - 1), central-difference time integration
// with a variable step, kinematic frictionless anvil at z = 0. Nodal masses: the element mass
// rho0 2 pi rbar A split equally to its four nodes (--mass rowsum: row sum of the consistent
// mass instead).
//
// Usage: fesph_axisym_taylor --case benchmark|ofhc [--nr N] [--end T] [--C c] [--chi x]
//        [--m m] [--edot0 r] [--thermal 0|1] [--V v] [--rate plastic|total] [--element q1|sri]
//        [--khg k] [--q1 c1] [--q2 c2] [--cfl c] [--mass equal|rowsum] [--profile FILE]
//        [--history DT] [--selftest]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Material {
  double rho0, E, nu;
  double A, B, n, C, m;     // Johnson-Cook
  double edot0;             // reference strain rate [1/s]
  double Troom, Tmelt, cp;  // [K], [K], [J/(kg K)]
  double chi;               // Taylor-Quinney fraction
  bool thermal;             // thermal softening on/off
  double G() const { return E / (2.0 * (1.0 + nu)); }
  double K() const { return E / (3.0 * (1.0 - 2.0 * nu)); }
};

struct Options {
  std::string caseName = "ofhc";
  int nr = 16;
  double tEnd = 80e-6;
  double cfl = 0.5;
  double khg = 0.1;  // hourglass coefficient
  double cq2 = 1.5, cq1 = 0.06;
  bool rateTotal = false;   // C-term rate: plastic (dlam/dt) or total sqrt(2/3 D':D')
  bool massRowSum = false;  // nodal mass: equal split of element mass, or row sum of consistent
  bool sri = false;         // element: one-point + hourglass (false) or selective-reduced 2x2
  std::string profile;
  double historyDt = 0.0;
  double L0 = 0, R0 = 0, V = 0;
  Material mat{};
};

// ---- element geometry at one configuration -----------------------------------------------
// Nodes 0..3 counter-clockwise in (r, z). b = centroid shape-function gradients
// (Flanagan-Belytschko mean gradients), rbar = r at the isoparametric centre (mean of the
// nodes), V = exact ring volume 2 pi int r dA, dV = dV/dx_a for the mean-dilatation forces.
struct Geo {
  double br[4], bz[4];
  double A, rbar, V;
  double dVdr[4], dVdz[4];
  double lmin;  // smallest altitude, for the time step
};

// full = false: gradients, area and rbar only (the mid-step kinematics).
void geometry(const double r[4], const double z[4], Geo& g, bool full = true) {
  g.A = 0.5 * ((r[2] - r[0]) * (z[3] - z[1]) + (r[1] - r[3]) * (z[2] - z[0]));
  const double inv2A = 0.5 / g.A;
  g.br[0] = (z[1] - z[3]) * inv2A;
  g.br[1] = (z[2] - z[0]) * inv2A;
  g.br[2] = (z[3] - z[1]) * inv2A;
  g.br[3] = (z[0] - z[2]) * inv2A;
  g.bz[0] = (r[3] - r[1]) * inv2A;
  g.bz[1] = (r[0] - r[2]) * inv2A;
  g.bz[2] = (r[1] - r[3]) * inv2A;
  g.bz[3] = (r[2] - r[0]) * inv2A;
  g.rbar = 0.25 * (r[0] + r[1] + r[2] + r[3]);
  if (!full) return;
  // Polygon first moment: int r dA = (1/6) sum (r_i + r_j)(r_i z_j - r_j z_i), j = i+1.
  double s[4], c[4], S = 0.0;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) & 3;
    s[i] = r[i] + r[j];
    c[i] = r[i] * z[j] - r[j] * z[i];
    S += s[i] * c[i];
  }
  const double f = 2.0 * kPi / 6.0;
  g.V = f * S;
  for (int k = 0; k < 4; ++k) {
    const int nx = (k + 1) & 3, pv = (k + 3) & 3;
    g.dVdr[k] = f * (c[k] + s[k] * z[nx] + c[pv] - s[pv] * z[pv]);
    g.dVdz[k] = f * (-s[k] * r[nx] + s[pv] * r[pv]);
  }
  // smallest distance of a node to the line of an edge it is not on (squared, one sqrt)
  double d2min = 1e300;
  for (int k = 0; k < 4; ++k) {
    const int nx = (k + 1) & 3, o1 = (k + 2) & 3, o2 = (k + 3) & 3;
    const double er = r[nx] - r[k], ez = z[nx] - z[k];
    const double c1 = er * (z[o1] - z[k]) - ez * (r[o1] - r[k]);
    const double c2 = er * (z[o2] - z[k]) - ez * (r[o2] - r[k]);
    d2min = std::min(d2min, std::min(c1 * c1, c2 * c2) / (er * er + ez * ez));
  }
  g.lmin = std::sqrt(d2min);
}

// Volume only (the ring volume at x^{n+1}).
double ringVolume(const double r[4], const double z[4]) {
  double S = 0.0;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) & 3;
    S += (r[i] + r[j]) * (r[i] * z[j] - r[j] * z[i]);
  }
  return 2.0 * kPi / 6.0 * S;
}

// 2x2 Gauss points of the bilinear quad for the selective-reduced element: shape functions,
// their (r, z) gradients, the radius and the volume weight w = 2 pi r det J (the four weights
// add up to the exact ring volume).
struct GaussPt {
  double N[4], dNr[4], dNz[4];
  double r, w;
};

void gaussPoints(const double r[4], const double z[4], GaussPt gp[4]) {
  const double c = 1.0 / std::sqrt(3.0);
  const double xa[4] = {-1, 1, 1, -1}, ea[4] = {-1, -1, 1, 1};
  for (int k = 0; k < 4; ++k) {
    const double X = xa[k] * c, Y = ea[k] * c;
    GaussPt& g = gp[k];
    double dNx[4], dNy[4];
    double J11 = 0, J12 = 0, J21 = 0, J22 = 0;
    g.r = 0;
    for (int a = 0; a < 4; ++a) {
      g.N[a] = 0.25 * (1 + xa[a] * X) * (1 + ea[a] * Y);
      dNx[a] = 0.25 * xa[a] * (1 + ea[a] * Y);
      dNy[a] = 0.25 * ea[a] * (1 + xa[a] * X);
      g.r += g.N[a] * r[a];
      J11 += dNx[a] * r[a];
      J12 += dNx[a] * z[a];
      J21 += dNy[a] * r[a];
      J22 += dNy[a] * z[a];
    }
    const double det = J11 * J22 - J12 * J21;
    if (!(det > 0.0)) throw std::runtime_error("non-positive Jacobian at a Gauss point");
    for (int a = 0; a < 4; ++a) {
      g.dNr[a] = (J22 * dNx[a] - J12 * dNy[a]) / det;
      g.dNz[a] = (-J21 * dNx[a] + J11 * dNy[a]) / det;
    }
    g.w = 2.0 * kPi * g.r * det;
  }
}

// ---- Johnson-Cook -------------------------------------------------------------------------
struct JC {
  const Material* M;
  double thermalFactor;  // 1 - T*^m, frozen over the step (explicit in T)
  double hard(double ep) const { return M->A + (ep > 0.0 ? M->B * powN(ep) : 0.0); }
  double powN(double e) const { return M->n == 1.0 ? e : std::pow(e, M->n); }
  double rateFactor(double rate) const {
    return 1.0 + M->C * std::log(std::max(1.0, rate / M->edot0));
  }
  double sy(double ep, double rate) const { return hard(ep) * rateFactor(rate) * thermalFactor; }
};

// Radial return: solves g(dl) = seq_tr - 3 G dl - sy(ep + dl, rate(dl)) = 0 with Newton,
// falling back to bisection inside the bracket [0, seq_tr / 3G] (g is monotone decreasing and
// d sy / d ep is unbounded at ep = 0 for n < 1). rateFixed < 0: rate = dl / dt (plastic rate).
double returnMap(const JC& jc, double seqTr, double ep, double G, double dt, double rateFixed,
                 double& syOut) {
  auto rateOf = [&](double dl) { return rateFixed >= 0.0 ? rateFixed : dl / dt; };
  const double g0 = seqTr - jc.sy(ep, rateOf(0.0));
  if (g0 <= 0.0) {
    syOut = jc.sy(ep, rateOf(0.0));
    return 0.0;
  }
  const Material& M = *jc.M;
  double lo = 0.0, hi = seqTr / (3.0 * G);
  double dl = g0 / (3.0 * G);  // perfectly plastic guess, inside the bracket
  for (int it = 0; it < 200; ++it) {
    const double e = ep + dl, rate = rateOf(dl);
    const double en = e > 0.0 ? jc.powN(e) : 0.0;
    const double hard = M.A + M.B * en, rf = jc.rateFactor(rate);
    const double g = seqTr - 3.0 * G * dl - hard * rf * jc.thermalFactor;
    if (std::fabs(g) <= 1e-12 * seqTr || hi - lo <= 1e-15 * hi) break;
    if (g > 0.0)
      lo = dl;
    else
      hi = dl;
    double dsy = (e > 0.0 ? M.B * M.n * en / e : 1e300) * rf * jc.thermalFactor;
    if (rateFixed < 0.0 && rate > M.edot0) dsy += hard * M.C / rate / dt * jc.thermalFactor;
    double next = dl + g / (3.0 * G + dsy);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    dl = next;
  }
  syOut = jc.sy(ep + dl, rateOf(dl));
  return dl;
}

// ---- material point -----------------------------------------------------------------------
struct Point {
  double srr = 0, szz = 0, stt = 0, srz = 0;  // deviatoric Cauchy stress
  double ep = 0, T = 0;                       // equivalent plastic strain, temperature
};

// Velocity gradient at a point: D_rr, D_zz, D_tt (hoop), D_rz and the spin W_rz.
struct Rate {
  double rr, zz, tt, rz, w;
};

// One step of the hypoelastic-plastic update. Returns the deviatoric stress power integrated
// over the step per unit volume (trapezoidal) and the plastic work per unit volume.
void updatePoint(const Options& opt, Point& P, const Rate& L, double dt, double rho,
                 double& devWork, double& plastWork) {
  const Material& M = opt.mat;
  const double G = M.G();
  const double tr = (L.rr + L.zz + L.tt) / 3.0;
  const double Drr = L.rr - tr, Dzz = L.zz - tr, Dtt = L.tt - tr, Drz = L.rz;
  const double s0rr = P.srr, s0zz = P.szz, s0tt = P.stt, s0rz = P.srz;
  // Jaumann: s_dot = 2G D' + W s - s W, with W_rz = w; the hoop component does not rotate
  double trr = s0rr + dt * (2 * G * Drr + 2 * L.w * s0rz);
  double tzz = s0zz + dt * (2 * G * Dzz - 2 * L.w * s0rz);
  double ttt = s0tt + dt * (2 * G * Dtt);
  double trz = s0rz + dt * (2 * G * Drz + L.w * (s0zz - s0rr));
  const double m3 = (trr + tzz + ttt) / 3;  // keep it exactly deviatoric (rounding)
  trr -= m3;
  tzz -= m3;
  ttt -= m3;
  const double seq = std::sqrt(1.5 * (trr * trr + tzz * tzz + ttt * ttt + 2 * trz * trz));
  double tf = 1.0;
  if (M.thermal) {
    const double Ts = std::clamp((P.T - M.Troom) / (M.Tmelt - M.Troom), 0.0, 1.0);
    tf = 1.0 - std::pow(Ts, M.m);
  }
  const JC jc{&M, tf};
  const double rateFixed =
      opt.rateTotal ? std::sqrt(2.0 / 3.0 * (Drr * Drr + Dzz * Dzz + Dtt * Dtt + 2 * Drz * Drz))
                    : -1.0;
  double sy = 0.0, dl = 0.0;
  if (seq > 0.0) dl = returnMap(jc, seq, P.ep, G, dt, rateFixed, sy);
  plastWork = 0.0;
  if (dl > 0.0) {
    const double f = 1.0 - 3.0 * G * dl / seq;
    trr *= f;
    tzz *= f;
    ttt *= f;
    trz *= f;
    P.ep += dl;
    plastWork = sy * dl;
    P.T += M.chi * plastWork / (rho * M.cp);
  }
  P.srr = trr;
  P.szz = tzz;
  P.stt = ttt;
  P.srz = trz;
  devWork = dt * 0.5 *
            ((s0rr + trr) * Drr + (s0zz + tzz) * Dzz + (s0tt + ttt) * Dtt + 2 * (s0rz + trz) * Drz);
}

// ---- the model ----------------------------------------------------------------------------
struct Model {
  Options opt;
  int nr = 0, nz = 0, nn = 0, ne = 0, ngp = 1;
  std::vector<double> r, z, vr, vz, mass, fr, fz, fqr, fqz, fhr, fhz;
  std::vector<int> conn;                   // 4 per element, counter-clockwise
  std::vector<double> p, q, V0, me, Vcur;  // per element
  std::vector<Point> pts;                  // ngp per element

  // energies [J]
  double KE0 = 0, Eint = 0, Eplast = 0, Eq = 0, Ehg = 0, Econt = 0, Wstress = 0;
  long steps = 0;
  double t = 0;
  int dtElem = -1;  // element that limits the time step

  int node(int i, int j) const { return j * (nr + 1) + i; }

  void gather(int e, const std::vector<double>& X, const std::vector<double>& Y, double* x,
              double* y) const {
    for (int a = 0; a < 4; ++a) {
      x[a] = X[conn[4 * e + a]];
      y[a] = Y[conn[4 * e + a]];
    }
  }

  double waveSpeed(double rho) const {
    const Material& M = opt.mat;
    return std::sqrt((M.K() + 4.0 / 3.0 * M.G()) / rho);
  }

  void build() {
    nr = opt.nr;
    nz = std::max(1, (int)std::lround(nr * opt.L0 / opt.R0));
    nn = (nr + 1) * (nz + 1);
    ne = nr * nz;
    ngp = opt.sri ? 4 : 1;
    r.assign(nn, 0);
    z.assign(nn, 0);
    vr.assign(nn, 0);
    vz.assign(nn, -opt.V);
    mass.assign(nn, 0);
    for (int j = 0; j <= nz; ++j)
      for (int i = 0; i <= nr; ++i) {
        r[node(i, j)] = opt.R0 * i / nr;
        z[node(i, j)] = opt.L0 * j / nz;
      }
    conn.resize(4 * ne);
    for (int j = 0; j < nz; ++j)
      for (int i = 0; i < nr; ++i) {
        int* c = &conn[4 * (j * nr + i)];
        c[0] = node(i, j);
        c[1] = node(i + 1, j);
        c[2] = node(i + 1, j + 1);
        c[3] = node(i, j + 1);
      }
    for (auto* v : {&p, &q, &V0, &me, &Vcur}) v->assign(ne, 0.0);
    Point p0;
    p0.T = opt.mat.Troom;
    pts.assign((size_t)ne * ngp, p0);
    const double rho0 = opt.mat.rho0;
    for (int e = 0; e < ne; ++e) {
      double er[4], ez[4];
      gather(e, r, z, er, ez);
      V0[e] = Vcur[e] = ringVolume(er, ez);
      me[e] = rho0 * V0[e];
      if (!opt.massRowSum) {
        // equal split of the element mass rho0 2 pi rbar A (volume weighting)
        for (int a = 0; a < 4; ++a) mass[conn[4 * e + a]] += 0.25 * me[e];
      } else {
        // row sum of the consistent mass: m_a = rho0 int N_a dV
        GaussPt gp[4];
        gaussPoints(er, ez, gp);
        for (int k = 0; k < 4; ++k)
          for (int a = 0; a < 4; ++a) mass[conn[4 * e + a]] += rho0 * gp[k].N[a] * gp[k].w;
      }
    }
    for (auto* v : {&fr, &fz, &fqr, &fqz, &fhr, &fhz}) v->assign(nn, 0.0);
    for (int a = 0; a < nn; ++a) KE0 += 0.5 * mass[a] * opt.V * opt.V;
  }

  // Internal forces at x^n from sigma^n, the bulk viscosity q (from the last step's rate) and
  // the hourglass viscosity on v^{n-1/2}. f_a = -int B_a^T s dV + (p + q) dV/dx_a: the
  // deviatoric part on the centroid (Q1) or 2x2 Gauss (SRI) B with the hoop row N_a / r, the
  // pressure conjugate to the exact volume rate (mean dilatation). Returns the stable step.
  double forces() {
    for (auto* v : {&fr, &fz, &fqr, &fqz, &fhr, &fhz}) std::fill(v->begin(), v->end(), 0.0);
    double dtMin = 1e300;
    static const double h[4] = {1, -1, 1, -1};
    for (int e = 0; e < ne; ++e) {
      double er[4], ez[4], evr[4], evz[4];
      gather(e, r, z, er, ez);
      gather(e, vr, vz, evr, evz);
      Geo g;
      geometry(er, ez, g);
      if (g.A <= 0.0 || g.V <= 0.0)
        throw std::runtime_error("inverted element " + std::to_string(e));
      Vcur[e] = g.V;
      const double rho = me[e] / g.V;
      const double c = waveSpeed(rho);
      const int* cn = &conn[4 * e];
      for (int a = 0; a < 4; ++a) {
        fr[cn[a]] += p[e] * g.dVdr[a];
        fz[cn[a]] += p[e] * g.dVdz[a];
        fqr[cn[a]] += q[e] * g.dVdr[a];
        fqz[cn[a]] += q[e] * g.dVdz[a];
      }
      if (!opt.sri) {
        const Point& P = pts[e];
        // hoop row at the centroid: N_a / r = 1 / (4 rbar)
        for (int a = 0; a < 4; ++a) {
          fr[cn[a]] -= g.V * (P.srr * g.br[a] + P.srz * g.bz[a] + P.stt * 0.25 / g.rbar);
          fz[cn[a]] -= g.V * (P.srz * g.br[a] + P.szz * g.bz[a]);
        }
        // Flanagan-Belytschko hourglass vector: orthogonal to all linear fields
        double hr = 0, hz = 0;
        for (int a = 0; a < 4; ++a) {
          hr += h[a] * er[a];
          hz += h[a] * ez[a];
        }
        double gam[4], qr = 0, qz = 0;
        for (int a = 0; a < 4; ++a) {
          gam[a] = h[a] - hr * g.br[a] - hz * g.bz[a];
          qr += gam[a] * evr[a];
          qz += gam[a] * evz[a];
        }
        // viscosity ~ khg rho c times a ring surface 2 pi rbar sqrt(A)
        const double ah = opt.khg * rho * c * 2.0 * kPi * g.rbar * std::sqrt(g.A);
        for (int a = 0; a < 4; ++a) {
          fhr[cn[a]] -= ah * gam[a] * qr;
          fhz[cn[a]] -= ah * gam[a] * qz;
        }
      } else {
        GaussPt gp[4];
        gaussPoints(er, ez, gp);
        for (int k = 0; k < 4; ++k) {
          const Point& P = pts[4 * e + k];
          const GaussPt& G = gp[k];
          for (int a = 0; a < 4; ++a) {
            fr[cn[a]] -= G.w * (P.srr * G.dNr[a] + P.srz * G.dNz[a] + P.stt * G.N[a] / G.r);
            fz[cn[a]] -= G.w * (P.srz * G.dNr[a] + P.szz * G.dNz[a]);
          }
        }
      }
      // time step with the bulk-viscosity correction
      double divv = 0.0;
      for (int a = 0; a < 4; ++a) divv += g.dVdr[a] * evr[a] + g.dVdz[a] * evz[a];
      divv /= g.V;
      const double Q = divv < 0.0 ? opt.cq1 * c + opt.cq2 * g.lmin * std::fabs(divv) : 0.0;
      const double dte = g.lmin / (Q + std::sqrt(Q * Q + c * c));
      if (dte < dtMin) {
        dtMin = dte;
        dtElem = e;
      }
    }
    return opt.cfl * dtMin;
  }

  // Stress update from x^n to x^{n+1} with v^{n+1/2} on the mid-step geometry; accumulates
  // the constitutive energy (trapezoidal stress power).
  void updateStress(const std::vector<double>& rOld, const std::vector<double>& zOld, double dt) {
    const double K = opt.mat.K();
    for (int e = 0; e < ne; ++e) {
      double r0[4], z0[4], r1[4], z1[4], rm[4], zm[4], evr[4], evz[4];
      gather(e, rOld, zOld, r0, z0);
      gather(e, r, z, r1, z1);
      gather(e, vr, vz, evr, evz);
      for (int a = 0; a < 4; ++a) {
        rm[a] = 0.5 * (r0[a] + r1[a]);
        zm[a] = 0.5 * (z0[a] + z1[a]);
      }
      const double Vn = Vcur[e], Vn1 = ringVolume(r1, z1), Vm = 0.5 * (Vn + Vn1);
      const double rhoNew = me[e] / Vn1;
      double devW = 0.0, plW = 0.0, areaMid = 0.0;
      if (!opt.sri) {
        Geo gm;
        geometry(rm, zm, gm, false);
        areaMid = gm.A;
        Rate L{0, 0, 0, 0, 0};
        double drz = 0, dzr = 0, vrc = 0;
        for (int a = 0; a < 4; ++a) {
          L.rr += gm.br[a] * evr[a];
          L.zz += gm.bz[a] * evz[a];
          drz += gm.bz[a] * evr[a];  // d v_r / d z
          dzr += gm.br[a] * evz[a];  // d v_z / d r
          vrc += 0.25 * evr[a];
        }
        L.tt = vrc / gm.rbar;
        L.rz = 0.5 * (drz + dzr);
        L.w = 0.5 * (drz - dzr);
        updatePoint(opt, pts[e], L, dt, rhoNew, devW, plW);
        devW *= Vm;
        plW *= Vm;
      } else {
        GaussPt gp[4];
        gaussPoints(rm, zm, gp);
        const double Vgp = gp[0].w + gp[1].w + gp[2].w + gp[3].w;
        for (int k = 0; k < 4; ++k) {
          const GaussPt& G = gp[k];
          Rate L{0, 0, 0, 0, 0};
          double drz = 0, dzr = 0, vrg = 0;
          for (int a = 0; a < 4; ++a) {
            L.rr += G.dNr[a] * evr[a];
            L.zz += G.dNz[a] * evz[a];
            drz += G.dNz[a] * evr[a];
            dzr += G.dNr[a] * evz[a];
            vrg += G.N[a] * evr[a];
          }
          L.tt = vrg / G.r;
          L.rz = 0.5 * (drz + dzr);
          L.w = 0.5 * (drz - dzr);
          double dW, pW;
          updatePoint(opt, pts[4 * e + k], L, dt, rhoNew, dW, pW);
          // weights at the mid geometry, scaled to the mid volume Vm
          devW += dW * G.w * Vm / Vgp;
          plW += pW * G.w * Vm / Vgp;
        }
        areaMid = 0.5 * ((rm[2] - rm[0]) * (zm[3] - zm[1]) + (rm[1] - rm[3]) * (zm[2] - zm[0]));
      }
      Eplast += plW;
      const double pn = p[e];
      const double pn1 = K * (V0[e] / Vn1 - 1.0);  // linear EOS
      p[e] = pn1;
      Eint += devW - 0.5 * (pn + pn1) * (Vn1 - Vn);
      // bulk viscosity (used by the next force evaluation) on the exact volume rate
      const double trD = (Vn1 - Vn) / (dt * Vm);
      const double l = std::sqrt(areaMid);
      q[e] = trD < 0.0 ? rhoNew * l * (opt.cq2 * l * trD * trD - opt.cq1 * waveSpeed(rhoNew) * trD)
                       : 0.0;
      Vcur[e] = Vn1;
    }
  }

  double kinetic() const {
    double k = 0;
    for (int a = 0; a < nn; ++a) k += 0.5 * mass[a] * (vr[a] * vr[a] + vz[a] * vz[a]);
    return k;
  }

  // Stored elastic energy: s:s / 4G per unit volume plus the linear EOS's
  // K ((V - V0) - V0 ln(V / V0)).
  double elasticEnergy() const {
    const Material& M = opt.mat;
    const double G = M.G(), K = M.K();
    double E = 0;
    for (int e = 0; e < ne; ++e) {
      for (int k = 0; k < ngp; ++k) {
        const Point& P = pts[(size_t)e * ngp + k];
        const double ss = P.srr * P.srr + P.szz * P.szz + P.stt * P.stt + 2 * P.srz * P.srz;
        E += Vcur[e] / ngp * ss / (4 * G);  // equal weights are exact enough for a report
      }
      E += K * ((Vcur[e] - V0[e]) - V0[e] * std::log(Vcur[e] / V0[e]));
    }
    return E;
  }

  double maxOf(double Point::*field) const {
    double m = 0;
    for (const Point& P : pts) m = std::max(m, P.*field);
    return m;
  }

  double length() const {
    return *std::max_element(z.begin(), z.end()) - *std::min_element(z.begin(), z.end());
  }
  double footRadius() const {
    double rm = 0;
    for (int a = 0; a < nn; ++a)
      if (z[a] < 0.5e-3) rm = std::max(rm, r[a]);
    return rm;
  }

  void run() {
    std::vector<double> rOld(nn), zOld(nn), vrPrev(nn), vzPrev(nn);
    double dtPrev = 0.0, dt0 = 0.0;
    double nextHist = 0.0;
    if (opt.historyDt > 0)
      std::printf(
          "# t[us] length[mm] footR[mm] KE/KE0 Eint/KE0 Eq/KE0 Ehg/KE0 Econt/KE0 dt[ns] "
          "limiting element (i, j)\n");
    while (t < opt.tEnd * (1 - 1e-12)) {
      double dt = forces();
      if (steps == 0) dt0 = dt;
      // a collapsing element would make the run endless: stop and say where
      if (dt < 1e-3 * dt0)
        throw std::runtime_error("time step collapsed to " + std::to_string(dt * 1e9) +
                                 " ns at element (i, j) = (" + std::to_string(dtElem % nr) + ", " +
                                 std::to_string(dtElem / nr) + ")");
      dt = std::min(dt, opt.tEnd - t);
      // central difference with a variable step: v^{n+1/2} = v^{n-1/2} + dt^n a^n
      const double dtAvg = steps == 0 ? 0.5 * dt : 0.5 * (dtPrev + dt);
      vrPrev = vr;
      vzPrev = vz;
      for (int a = 0; a < nn; ++a) {
        vr[a] += dtAvg * (fr[a] + fqr[a] + fhr[a]) / mass[a];
        vz[a] += dtAvg * (fz[a] + fqz[a] + fhz[a]) / mass[a];
      }
      for (int j = 0; j <= nz; ++j) vr[node(0, j)] = 0.0;  // axis
      // kinematic frictionless anvil: land exactly on z = 0. The wall impulse I = m dv does
      // work I * vbar (zero on a node that rests on the wall); that work is the energy lost.
      for (int a = 0; a < nn; ++a) {
        if (z[a] + dt * vz[a] < 0.0) {
          const double vnew = -z[a] / dt;
          Econt -= mass[a] * (vnew - vz[a]) * 0.5 * (vzPrev[a] + vnew);
          vz[a] = vnew;
        }
      }
      // work of the force parts over the step on the corrected velocities:
      // KE change = (dtAvg f + I) . vbar exactly
      for (int a = 0; a < nn; ++a) {
        const double ar = 0.5 * (vrPrev[a] + vr[a]), az = 0.5 * (vzPrev[a] + vz[a]);
        Wstress -= dtAvg * (fr[a] * ar + fz[a] * az);
        Eq -= dtAvg * (fqr[a] * ar + fqz[a] * az);
        Ehg -= dtAvg * (fhr[a] * ar + fhz[a] * az);
      }
      rOld = r;
      zOld = z;
      for (int a = 0; a < nn; ++a) {
        r[a] += dt * vr[a];
        z[a] = std::max(0.0, z[a] + dt * vz[a]);  // max: rounding only
      }
      updateStress(rOld, zOld, dt);
      t += dt;
      dtPrev = dt;
      ++steps;
      if (opt.historyDt > 0 && t >= nextHist) {
        const double ke = kinetic();
        std::printf("%8.3f %9.4f %8.4f %9.5f %9.5f %9.5f %9.5f %9.5f %7.3f (%d, %d)\n", t * 1e6,
                    length() * 1e3, footRadius() * 1e3, ke / KE0, Eint / KE0, Eq / KE0, Ehg / KE0,
                    Econt / KE0, dt * 1e9, dtElem % nr, dtElem / nr);
        std::fflush(stdout);
        nextHist += opt.historyDt;
      }
    }
  }
};

// ---- self test: geometry, derivatives, patch test -----------------------------------------
int selftest() {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-0.2, 0.2);
  int bad = 0;
  for (int trial = 0; trial < 100; ++trial) {
    double r[4] = {0.0, 1.0, 1.0, 0.0}, z[4] = {0.0, 0.0, 1.0, 1.0};
    const double shift = trial % 2 ? 0.0 : 1.5;  // half the tests touch the axis
    for (int a = 0; a < 4; ++a) {
      r[a] += shift + (shift > 0 || (a == 1 || a == 2) ? U(rng) : 0.0);
      z[a] += U(rng);
    }
    Geo g;
    geometry(r, z, g);
    // dV/dx against central differences
    const double hstep = 1e-6;
    for (int a = 0; a < 4; ++a) {
      double rp[4], rmn[4], zp[4], zmn[4];
      std::copy(r, r + 4, rp);
      std::copy(r, r + 4, rmn);
      std::copy(z, z + 4, zp);
      std::copy(z, z + 4, zmn);
      rp[a] += hstep;
      rmn[a] -= hstep;
      zp[a] += hstep;
      zmn[a] -= hstep;
      Geo a1, a2, a3, a4;
      geometry(rp, z, a1);
      geometry(rmn, z, a2);
      geometry(r, zp, a3);
      geometry(r, zmn, a4);
      const double fdr = (a1.V - a2.V) / (2 * hstep), fdz = (a3.V - a4.V) / (2 * hstep);
      if (std::fabs(fdr - g.dVdr[a]) > 1e-6 * (1 + std::fabs(fdr)) ||
          std::fabs(fdz - g.dVdz[a]) > 1e-6 * (1 + std::fabs(fdz)))
        ++bad;
    }
    // linear velocity field: v_r = a0 + a1 r + a2 z, v_z = b0 + b1 r + b2 z. Gradients exact,
    // hourglass rate zero.
    const double a0 = 0.3, a1 = 0.7, a2 = -0.4, b0 = 0.1, b1 = 0.25, b2 = -0.9;
    double drr = 0, dzz = 0, drz = 0, dzr = 0, qr = 0, qz = 0, hr = 0, hz = 0;
    const double hv[4] = {1, -1, 1, -1};
    for (int a = 0; a < 4; ++a) {
      hr += hv[a] * r[a];
      hz += hv[a] * z[a];
    }
    for (int a = 0; a < 4; ++a) {
      const double vr = a0 + a1 * r[a] + a2 * z[a], vz = b0 + b1 * r[a] + b2 * z[a];
      drr += g.br[a] * vr;
      dzz += g.bz[a] * vz;
      drz += g.bz[a] * vr;
      dzr += g.br[a] * vz;
      const double gam = hv[a] - hr * g.br[a] - hz * g.bz[a];
      qr += gam * vr;
      qz += gam * vz;
    }
    if (std::fabs(drr - a1) > 1e-12 || std::fabs(dzz - b2) > 1e-12 || std::fabs(drz - a2) > 1e-12 ||
        std::fabs(dzr - b1) > 1e-12 || std::fabs(qr) > 1e-12 || std::fabs(qz) > 1e-12)
      ++bad;
  }
  // Gauss points: weights add up to the ring volume; linear fields and the hoop rate of
  // v_r = a r are exact at every point
  for (int trial = 0; trial < 20; ++trial) {
    double r[4] = {0.0, 1.0, 1.1, 0.0}, z[4] = {0.0, 0.1, 1.0, 0.9};
    for (int a = 1; a < 3; ++a) {
      r[a] += U(rng);
      z[a] += U(rng);
    }
    GaussPt gp[4];
    gaussPoints(r, z, gp);
    double W = 0;
    for (int k = 0; k < 4; ++k) {
      W += gp[k].w;
      double drr = 0, dzr = 0, hoop = 0;
      for (int a = 0; a < 4; ++a) {
        drr += gp[k].dNr[a] * (0.7 * r[a] - 0.2 * z[a]);
        dzr += gp[k].dNz[a] * (0.7 * r[a] - 0.2 * z[a]);
        hoop += gp[k].N[a] * 0.7 * r[a];
      }
      if (std::fabs(drr - 0.7) > 1e-12 || std::fabs(dzr + 0.2) > 1e-12 ||
          std::fabs(hoop / gp[k].r - 0.7) > 1e-12)
        ++bad;
    }
    if (std::fabs(W - ringVolume(r, z)) > 1e-12 * W) ++bad;
  }
  // Patch test: uniform uniaxial stress sigma_zz = -S in a bar (sigma_rr = sigma_tt = 0).
  // Every node off the end faces must be in equilibrium (this checks the hoop row against
  // the volume derivative), and the end faces must carry S pi R^2.
  for (int sri = 0; sri < 2; ++sri) {
    Model md;
    md.opt.nr = 3;
    md.opt.L0 = 2e-3;
    md.opt.R0 = 1e-3;
    md.opt.V = 0.0;
    md.opt.sri = sri;
    md.opt.mat =
        Material{8930, 117e9, 0.35, 400e6, 1e8, 1.0, 0.0, 1.0, 1.0, 293, 1356, 383, 0.9, false};
    md.build();
    const double S = 1e8;
    for (Point& P : md.pts) {
      P.srr = S / 3;
      P.szz = -2 * S / 3;
      P.stt = S / 3;
    }
    for (int e = 0; e < md.ne; ++e) md.p[e] = S / 3;
    md.forces();
    const double scale = S * md.opt.R0 * md.opt.R0;
    double top = 0, worst = 0;
    for (int j = 0; j <= md.nz; ++j)
      for (int i = 0; i <= md.nr; ++i) {
        const int a = md.node(i, j);
        if (j == md.nz) top += md.fz[a];
        if (j == 0 || j == md.nz) {
          worst = std::max(worst, i > 0 ? std::fabs(md.fr[a]) : 0.0);
          continue;
        }
        worst = std::max(worst, std::fabs(md.fz[a]));
        if (i > 0) worst = std::max(worst, std::fabs(md.fr[a]));
      }
    if (worst > 1e-12 * scale || std::fabs(top - S * kPi * md.opt.R0 * md.opt.R0) > 1e-12 * scale) {
      std::printf("patch test (%s): worst residual %.3g, top force %.6g vs %.6g\n",
                  sri ? "sri" : "q1", worst / scale, top, S * kPi * md.opt.R0 * md.opt.R0);
      ++bad;
    }
  }
  // exact volume of a cylinder ring
  {
    double r[4] = {1, 2, 2, 1}, z[4] = {0, 0, 3, 3};
    Geo g;
    geometry(r, z, g);
    if (std::fabs(g.V - kPi * (4 - 1) * 3) > 1e-12) ++bad;
  }
  // return map: perfectly plastic with linear hardening has the closed form
  {
    Material M{};
    M.A = 400e6;
    M.B = 1e8;
    M.n = 1;
    M.C = 0;
    M.edot0 = 1;
    M.thermal = false;
    JC jc{&M, 1.0};
    const double G = 43e9, seq = 600e6, ep0 = 0.1, dt = 1e-8;
    double sy;
    const double dl = returnMap(jc, seq, ep0, G, dt, -1.0, sy);
    const double exact = (seq - 400e6 - 1e8 * ep0) / (3 * G + 1e8);
    if (std::fabs(dl - exact) > 1e-12 * exact) ++bad;
    // rate-dependent: residual must vanish
    M.B = 292e6;
    M.n = 0.31;
    M.C = 0.025;
    const double dl2 = returnMap(jc, seq, 0.0, G, dt, -1.0, sy);
    if (std::fabs(seq - 3 * G * dl2 - sy) > 1e-6 * seq) ++bad;
  }
  std::printf("selftest: %s (%d failures)\n", bad ? "FAILED" : "passed", bad);
  return bad ? 1 : 0;
}

[[noreturn]] void usage(const char* msg) {
  std::fprintf(stderr, "error: %s\n", msg);
  std::fprintf(stderr,
               "usage: fesph_axisym_taylor --case benchmark|ofhc [--nr N] [--end T] [--C c] "
               "[--chi x] [--m m] [--edot0 r] [--thermal 0|1] [--V v] [--rate plastic|total] "
               "[--element q1|sri] [--khg k] [--q1 c1] [--q2 c2] [--cfl c] [--mass equal|rowsum] "
               "[--profile FILE] "
               "[--history DT] [--selftest]\n");
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::vector<std::pair<std::string, std::string>> kv;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--selftest") return selftest();
    if (a.rfind("--", 0) != 0 || i + 1 >= argc) usage(("bad argument " + a).c_str());
    kv.emplace_back(a.substr(2), argv[++i]);
  }
  for (auto& [k, v] : kv)
    if (k == "case") o.caseName = v;
  Material& M = o.mat;
  if (o.caseName == "benchmark") {
    // Bilinear copper bar (code-to-code benchmark): JC with n = 1, C = 0, no softening.
    M = Material{8930, 117e9, 0.35, 400e6, 100085543.2, 1.0, 0.0,
                 1.0,  1.0,   293,  1356,  383,         0.9, false};
    o.L0 = 32.4e-3;
    o.R0 = 3.2e-3;
    o.V = 227.0;
  } else if (o.caseName == "ofhc") {
    // OFHC copper, Johnson & Cook 1983.
    M = Material{8960, 124e9, 0.34, 90e6, 292e6, 0.31, 0.025, 1.09, 1.0, 293, 1356, 383, 0.9, true};
    o.L0 = 25.4e-3;
    o.R0 = 3.81e-3;
    o.V = 190.0;
  } else {
    usage("unknown case");
  }
  for (auto& [k, v] : kv) {
    const char* s = v.c_str();
    if (k == "case")
      continue;
    else if (k == "nr")
      o.nr = std::atoi(s);
    else if (k == "end")
      o.tEnd = std::atof(s);
    else if (k == "C")
      M.C = std::atof(s);
    else if (k == "chi")
      M.chi = std::atof(s);
    else if (k == "edot0")
      M.edot0 = std::atof(s);
    else if (k == "q1")
      o.cq1 = std::atof(s);
    else if (k == "q2")
      o.cq2 = std::atof(s);
    else if (k == "m")
      M.m = std::atof(s);
    else if (k == "thermal")
      M.thermal = std::atoi(s) != 0;
    else if (k == "V")
      o.V = std::atof(s);
    else if (k == "rate") {
      if (v == "total")
        o.rateTotal = true;
      else if (v == "plastic")
        o.rateTotal = false;
      else
        usage("--rate plastic|total");
    } else if (k == "element") {
      if (v == "sri")
        o.sri = true;
      else if (v == "q1")
        o.sri = false;
      else
        usage("--element q1|sri");
    } else if (k == "khg")
      o.khg = std::atof(s);
    else if (k == "cfl")
      o.cfl = std::atof(s);
    else if (k == "mass") {
      if (v == "rowsum")
        o.massRowSum = true;
      else if (v == "equal")
        o.massRowSum = false;
      else
        usage("--mass equal|rowsum");
    } else if (k == "profile")
      o.profile = v;
    else if (k == "history")
      o.historyDt = std::atof(s);
    else
      usage(("unknown option --" + k).c_str());
  }
  if (o.nr < 1) usage("--nr must be >= 1");

  Model mdl;
  mdl.opt = o;
  mdl.build();
  std::printf(
      "case %s: L0 %.3f mm, R0 %.3f mm, V %.1f m/s, nr %d nz %d (%d elements), end %.1f us\n",
      o.caseName.c_str(), o.L0 * 1e3, o.R0 * 1e3, o.V, mdl.nr, mdl.nz, mdl.ne, o.tEnd * 1e6);
  std::printf(
      "  A %.4g B %.10g n %.3g C %.4g edot0 %.3g m %.3g thermal %d chi %.2f rate %s element %s khg "
      "%.3g "
      "q %.3g/%.3g cfl %.2f mass %s\n",
      M.A, M.B, M.n, M.C, M.edot0, M.m, (int)M.thermal, M.chi, o.rateTotal ? "total" : "plastic",
      o.sri ? "sri" : "q1", o.sri ? 0.0 : o.khg, o.cq2, o.cq1, o.cfl,
      o.massRowSum ? "rowsum" : "equal");
  const auto t0 = std::chrono::steady_clock::now();
  try {
    mdl.run();
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "run failed at t = %.4g us: %s\n", mdl.t * 1e6, ex.what());
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const double KE = mdl.kinetic(), Eel = mdl.elasticEnergy(), K0 = mdl.KE0;
  const double bal = KE + mdl.Eint + mdl.Eq + mdl.Ehg + mdl.Econt - K0;
  const double L = mdl.length(), Rf = mdl.footRadius();
  const double Rc = mdl.r[mdl.node(mdl.nr, 0)];
  double Rmax = *std::max_element(mdl.r.begin(), mdl.r.end());
  std::printf("result: t %.2f us, %ld steps, wall %.1f s\n", mdl.t * 1e6, mdl.steps, wall);
  std::printf("  final length      %.4f mm\n", L * 1e3);
  std::printf("  foot radius       %.4f mm (nodes with z < 0.5 mm), diameter %.4f mm\n", Rf * 1e3,
              2 * Rf * 1e3);
  // The foot's rim can curl up off the anvil: say how high the corner node sits.
  const double zmin = *std::min_element(mdl.z.begin(), mdl.z.end());
  std::printf("  corner node r     %.4f mm, %.4f mm above the lowest node (min z %.4g mm)\n",
              Rc * 1e3, (mdl.z[mdl.node(mdl.nr, 0)] - zmin) * 1e3, zmin * 1e3);
  std::printf("  max r             %.4f mm\n", Rmax * 1e3);
  std::printf("  max eps_p %.4f, max T %.1f K\n", mdl.maxOf(&Point::ep), mdl.maxOf(&Point::T));
  std::printf("energy [J] (KE0 %.4f):\n", K0);
  std::printf("  kinetic %.5f, internal %.5f (elastic %.5f + plastic work %.5f = %.5f)\n", KE,
              mdl.Eint, Eel, mdl.Eplast, Eel + mdl.Eplast);
  std::printf("  bulk viscosity %.5f, hourglass %.5f (%.3f %% of KE0), anvil %.5f (%.3f %%)\n",
              mdl.Eq, mdl.Ehg, 100 * mdl.Ehg / K0, mdl.Econt, 100 * mdl.Econt / K0);
  std::printf(
      "  balance error %.3e J (%.4f %% of KE0); stress-force work %.5f vs constitutive %.5f\n", bal,
      100 * bal / K0, mdl.Wstress, mdl.Eint);
  if (!o.profile.empty()) {
    std::ofstream f(o.profile);
    // the outer surface from the impact face up, then the impact face from the axis out
    f << "surface,z_mm,r_mm\n";
    for (int j = 0; j <= mdl.nz; ++j) {
      const int a = mdl.node(mdl.nr, j);
      f << "side," << mdl.z[a] * 1e3 << "," << mdl.r[a] * 1e3 << "\n";
    }
    for (int i = 0; i <= mdl.nr; ++i) {
      const int a = mdl.node(i, 0);
      f << "face," << mdl.z[a] * 1e3 << "," << mdl.r[a] * 1e3 << "\n";
    }
    std::printf("profile written to %s\n", o.profile.c_str());
  }
  return 0;
}
