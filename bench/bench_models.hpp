#pragma once
// The models the benchmarks time: the example robots moved through a set of poses (same
// topology, new numbers), a straight cantilever chain of N beam links with its closed-form tip
// compliance, a space frame of about 1 000 beams, and the virtual joint model (VJM) of the
// six-axis robot written out plainly as the floor no general method beats.
#include <string>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"

namespace bench {

using stiffmsa::Mat6;
using stiffmsa::Model;
using stiffmsa::Vec3;

// ---- the example robots ------------------------------------------------------------------

// Reads examples/<file> from the source tree.
Model load_example(const std::string& file);

// `count` poses of examples/industrial-6axis.yaml: every joint turned by up to ±0.2–0.3 rad
// from the file's pose (product of exponentials about the file's joint axes), far from the
// wrist, elbow and shoulder singularities.
std::vector<Model> industrial_poses(const Model& home, int count);

// `count` poses of examples/gough-stewart-6ups.yaml: the platform moved by up to 2 cm and
// turned by up to 0.05 rad about the vertical; the legs' midpoints and actuator axes follow.
std::vector<Model> gough_stewart_poses(const Model& home, int count);

// `count` poses of examples/tripteron.yaml: the platform moved by up to 2 cm; each carriage
// follows along its rail and each leg's elbow is found by the planar two-link inverse
// kinematics on the file's side.
std::vector<Model> tripteron_poses(const Model& home, int count);

// The same model with every link rigid: the robot the virtual joint model describes.
Model with_rigid_links(Model model);

// ---- the virtual joint model of a serial robot -------------------------------------------

// Rigid links and elastic revolute joints: C = Σ J_i·k_i⁻¹·J_iᵀ, J_i = [a_i × (p_e − p_i); a_i].
struct VirtualJointModel {
  std::vector<Vec3> axes;            // unit joint axes a_i
  std::vector<Vec3> points;          // joint points p_i
  std::vector<double> stiffness;     // k_i (N·m/rad)
  Vec3 end_effector = Vec3::Zero();  // p_e
};

// The joints of a serial model with elastic revolute joints and one end effector.
VirtualJointModel virtual_joint_model(const Model& serial);

Mat6 vjm_compliance(const VirtualJointModel& vjm);

// ---- the straight chain ------------------------------------------------------------------

// Steel tube 100×5 mm, 10 m long along x, clamped at x = 0, split into `links` beam links
// (Euler–Bernoulli) joined rigidly; a 100 N tip load along −y; end effector `tip`.
struct ChainSpec {
  double length = 10.0;
  double E = 2.1e11, G = 8.0e10;
  double D = 0.1, t = 0.005;
};
Model cantilever_chain(int links, const ChainSpec& spec = {});

// Closed form of the tip compliance, order [dx, dy, dz, rx, ry, rz]: C_xx = L/(EA),
// C_yy = C_zz = L³/(3EI), C_rx = L/(GJ), C_ry = C_rz = L/(EI), C_y,rz = L²/(2EI),
// C_z,ry = −L²/(2EI).
Mat6 cantilever_tip_compliance(const ChainSpec& spec = {});

// Largest entry difference, each entry measured against √(|e_ii·e_jj|) of the expected matrix
// (the compliance mixes m/N, 1/N and rad/(N·m)).
double scaled_difference(const Mat6& actual, const Mat6& expected);

// ---- a space frame -----------------------------------------------------------------------

// A building frame: (nx+1)×(ny+1) steel columns per storey, beams along x and y on every
// floor, clamped at the ground, a lateral load at the top corner (also the end effector).
// nx = ny = 5 and 10 storeys give 960 beams.
Model space_frame(int nx, int ny, int storeys);

}  // namespace bench
