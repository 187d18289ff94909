// Pinocchio's own C++ time for the robot benchmark (bench/peers/robot.py builds and runs this).
// Usage: robot_cpp MODEL.bin CONFIGS.txt VELOCITIES.txt REPEAT CHUNK
// MODEL.bin: the (reduced) model saved by Pinocchio's Python bindings (model.saveToBinary), so
// both sides use the same model; CONFIGS.txt: first line "N NQ", then N lines of NQ numbers.
// VELOCITIES.txt: the same layout with NV numbers per line. Times REPEAT rounds over all
// configurations in chunks of CHUNK (as the Rust runner does): ccrba (FK + CoM + A_g), then
// ccrba + computeCentroidalMomentumTimeVariation(q, v, 0) (A_g and dA_g/dt v).
// Prints: "median_ns min_ns sink" for both timings, then for configuration 0 the CoM, A_g
// (row-major) and dA_g/dt v for the value check.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/centroidal.hpp>
#include <pinocchio/serialization.hpp>

int main(int argc, char** argv) {
  if (argc < 6) {
    std::cerr << "usage: robot_cpp MODEL.bin CONFIGS.txt VELOCITIES.txt REPEAT CHUNK\n";
    return 2;
  }
  pinocchio::Model model;
  model.loadFromBinary(argv[1]);
  pinocchio::Data data(model);
  std::ifstream in(argv[2]);
  int n = 0, nq = 0;
  in >> n >> nq;
  if (nq != model.nq) {
    std::cerr << "configurations have nq=" << nq << ", model has " << model.nq << "\n";
    return 2;
  }
  std::vector<Eigen::VectorXd> qs(n, Eigen::VectorXd(nq));
  for (auto& q : qs)
    for (int k = 0; k < nq; ++k) in >> q[k];
  std::ifstream vin(argv[3]);
  int nvl = 0, nv = 0;
  vin >> nvl >> nv;
  if (nvl != n || nv != model.nv) {
    std::cerr << "velocities: expected " << n << " x " << model.nv << "\n";
    return 2;
  }
  std::vector<Eigen::VectorXd> vs(n, Eigen::VectorXd(nv));
  for (auto& w : vs)
    for (int k = 0; k < nv; ++k) vin >> w[k];
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv);
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(model.nv);
  const int repeat = std::stoi(argv[4]);
  const int chunk = std::max(1, std::stoi(argv[5]));
  std::vector<double> per_config;
  double sink = 0;
  for (int r = 0; r < repeat; ++r) {
    for (int start = 0; start < n; start += chunk) {
      const int end = std::min(n, start + chunk);
      auto t0 = std::chrono::steady_clock::now();
      for (int k = start; k < end; ++k) {
        pinocchio::ccrba(model, data, qs[k], v);  // forward kinematics, CoM and A_g in one pass
        sink += data.Ag(3, 7) + data.com[0][0];
      }
      auto t1 = std::chrono::steady_clock::now();
      per_config.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / (end - start));
    }
  }
  std::sort(per_config.begin(), per_config.end());
  std::cout << std::setprecision(17) << per_config[per_config.size() / 2] << " " << per_config[0]
            << " " << sink << "\n";
  std::vector<double> dot_v;
  for (int r = 0; r < repeat; ++r) {
    for (int start = 0; start < n; start += chunk) {
      const int end = std::min(n, start + chunk);
      auto t0 = std::chrono::steady_clock::now();
      for (int k = start; k < end; ++k) {
        pinocchio::ccrba(model, data, qs[k], vs[k]);
        pinocchio::computeCentroidalMomentumTimeVariation(model, data, qs[k], vs[k], a);
        sink += data.Ag(3, 7) + data.dhg.angular()[1];
      }
      auto t1 = std::chrono::steady_clock::now();
      dot_v.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / (end - start));
    }
  }
  std::sort(dot_v.begin(), dot_v.end());
  std::cout << dot_v[dot_v.size() / 2] << " " << dot_v[0] << " " << sink << "\n";
  pinocchio::ccrba(model, data, qs[0], v);
  for (int k = 0; k < 3; ++k) std::cout << data.com[0][k] << (k < 2 ? " " : "\n");
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < model.nv; ++j) std::cout << data.Ag(i, j) << (j + 1 < model.nv ? " " : "\n");
  pinocchio::computeCentroidalMomentumTimeVariation(model, data, qs[0], vs[0], a);
  for (int k = 0; k < 3; ++k) std::cout << data.dhg.linear()[k] << " ";
  for (int k = 0; k < 3; ++k) std::cout << data.dhg.angular()[k] << (k < 2 ? " " : "\n");
  return 0;
}
