// Pinocchio's inverse dynamics (pinocchio::rnea) over N samples in a native C++ loop: the
// baseline our compiled batch inverse dynamics is compared with per sample, free of any Python
// call overhead. Built and driven by pinocchio_native.py (beside this file).
//
// Usage:
//   pinocchio_native URDF N Q QD QDD TAU_OUT REPEATS GX GY GZ [JOINT ...]
// Q, QD, QDD: raw row-major float64 (N, n) files, n = number of JOINT names given (our
// coordinate order; without names: every joint of the model, in Pinocchio's order). TAU_OUT
// receives tau in the same layout. G: gravity (a URDF has none, Pinocchio's default is -z).
//
// Each sample is what our batch function gets and gives: joint angles/positions, rates and
// accelerations in, torques out. URDF "continuous" joints are Pinocchio's unbounded revolutes
// (nq 2: cos q, sin q), so the packing (sincos included) is inside the timed loop, like the
// trig inside ours. A second, rnea-only timing runs on inputs packed beforehand.
//
// Prints "key value" lines: nq, nv, n, max_abs_tau, then ns per sample (best and median of
// REPEATS timed passes over all N samples, std::chrono::steady_clock) for the whole loop
// (best_ns, median_ns), for rnea alone (rnea_best_ns, rnea_median_ns) and for the joint-torque
// regressor on the same packed inputs (regressor_best_ns, regressor_median_ns), for the mass
// matrix (crba_best_ns, crba_median_ns; with every matrix written out: crba_stored_best_ns,
// crba_stored_median_ns) and the forward dynamics (aba_best_ns, aba_median_ns,
// fed rnea's torques) on them, and checksums (keep those loops from being optimised away).
// TAU_OUT.M receives every sample's mass matrix, (N, n, n) in our coordinate order and
// symmetric (crba fills the upper triangle), and TAU_OUT.qdd aba's accelerations (N, n): the
// caller checks them against its own.
//
// Compiled by pinocchio_native.py (flags there too):
//   c++ -std=c++17 -O3 -march=native -DNDEBUG
//       -DEIGEN_MAX_ALIGN_BYTES=16 -DEIGEN_MALLOC_ALREADY_ALIGNED=1
//       -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30
//       -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12
//       -DPINOCCHIO_WITH_URDFDOM -DPINOCCHIO_URDFDOM_HEADERS_{MAJOR,MINOR,PATCH}_VERSION=3,0,0
//       -I<cmeel.prefix>/include{,/urdfdom_headers,/urdfdom} -I<eigen3>
//       pinocchio_native.cpp -L<cmeel.prefix>/lib -Wl,-rpath,<cmeel.prefix>/lib
//       -lpinocchio_parsers -lpinocchio_default -lurdfdom_model
// Not defining PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION makes rnea a header template compiled
// here with -O3 -march=native (the wheel's prebuilt copy is generic x86-64). Only the URDF
// parsing crosses into the wheel's libraries, whose Eigen objects are laid out for 16-byte
// alignment and allocated with plain malloc: EIGEN_MAX_ALIGN_BYTES=16 keeps our layout the
// same under AVX, and EIGEN_MALLOC_ALREADY_ALIGNED=1 makes us free their vectors with plain
// free (Eigen 3.4 otherwise picks its handmade 64-byte aligned free under AVX-512 and the
// parser's Model crashes on destruction).

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/regressor.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

std::vector<double> read_doubles(const char * path, size_t count)
{
  std::vector<double> out(count);
  FILE * f = std::fopen(path, "rb");
  if (!f)
    throw std::runtime_error(std::string("cannot open ") + path);
  size_t got = std::fread(out.data(), sizeof(double), count, f);
  bool extra = std::fgetc(f) != EOF;
  std::fclose(f);
  if (got != count || extra)
    throw std::runtime_error(std::string(path) + ": expected exactly " + std::to_string(count)
                             + " float64 values");
  return out;
}

// One of our coordinates: where it goes in Pinocchio's q and v, and whether q holds (cos, sin).
struct Coord
{
  int iq, iv;
  bool unbounded;
};

double median(std::vector<double> x)
{
  std::sort(x.begin(), x.end());
  size_t m = x.size() / 2;
  return x.size() % 2 ? x[m] : 0.5 * (x[m - 1] + x[m]);
}

} // namespace

int main(int argc, char ** argv)
{
  if (argc < 11)
  {
    std::fprintf(stderr, "usage: %s URDF N Q QD QDD TAU_OUT REPEATS GX GY GZ [JOINT ...]\n",
                 argv[0]);
    return 2;
  }
  try
  {
    pinocchio::Model model;
    pinocchio::urdf::buildModel(std::string(argv[1]), model);
    model.gravity.linear() << std::atof(argv[8]), std::atof(argv[9]), std::atof(argv[10]);
    pinocchio::Data data(model);

    std::vector<Coord> coords;
    std::vector<pinocchio::JointIndex> joints;
    if (argc > 11)
      for (int k = 11; k < argc; ++k)
      {
        if (!model.existJointName(argv[k]))
          throw std::runtime_error(std::string("no joint named ") + argv[k] + " in " + argv[1]);
        joints.push_back(model.getJointId(argv[k]));
      }
    else
      for (pinocchio::JointIndex j = 1; j < (pinocchio::JointIndex)model.njoints; ++j)
        joints.push_back(j);
    for (auto j : joints)
    {
      if (model.nvs[j] != 1 || model.nqs[j] > 2)
        throw std::runtime_error("joint " + model.names[j] + " is not a 1-dof joint");
      coords.push_back({model.idx_qs[j], model.idx_vs[j], model.nqs[j] == 2});
    }
    const int n = (int)coords.size();
    if (n != model.nv)
      throw std::runtime_error("the joints named cover " + std::to_string(n) + " of nv = "
                               + std::to_string(model.nv) + " velocities");

    const long N = std::atol(argv[2]);
    const int R = std::atoi(argv[7]);
    if (N <= 0 || R <= 0)
      throw std::runtime_error("N and REPEATS must be positive");
    const std::vector<double> Q = read_doubles(argv[3], N * n);
    const std::vector<double> QD = read_doubles(argv[4], N * n);
    const std::vector<double> QDD = read_doubles(argv[5], N * n);
    std::vector<double> TAU(N * n);

    Eigen::VectorXd q = pinocchio::neutral(model), v(model.nv), a(model.nv);
    // the contract of our batch function: angles, rates, accelerations in; torques out
    auto full_pass = [&]() {
      for (long s = 0; s < N; ++s)
      {
        const double * qs = &Q[s * n];
        const double * qds = &QD[s * n];
        const double * qdds = &QDD[s * n];
        for (int i = 0; i < n; ++i)
        {
          const Coord & c = coords[i];
          if (c.unbounded)
          {
            q[c.iq] = std::cos(qs[i]);
            q[c.iq + 1] = std::sin(qs[i]);
          }
          else
            q[c.iq] = qs[i];
          v[c.iv] = qds[i];
          a[c.iv] = qdds[i];
        }
        pinocchio::rnea(model, data, q, v, a);
        double * taus = &TAU[s * n];
        for (int i = 0; i < n; ++i)
          taus[i] = data.tau[coords[i].iv];
      }
    };

    // warm-up and the checked result
    full_pass();
    {
      FILE * f = std::fopen(argv[6], "wb");
      if (!f || std::fwrite(TAU.data(), sizeof(double), TAU.size(), f) != TAU.size())
        throw std::runtime_error(std::string("cannot write ") + argv[6]);
      std::fclose(f);
    }
    double max_abs = 0.0;
    for (double t : TAU)
      max_abs = std::max(max_abs, std::fabs(t));

    using clock = std::chrono::steady_clock;
    auto time_passes = [&](auto && pass) {
      std::vector<double> ns(R);
      for (int r = 0; r < R; ++r)
      {
        auto t0 = clock::now();
        pass();
        auto t1 = clock::now();
        ns[r] = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(N);
      }
      return ns;
    };
    std::vector<double> full = time_passes(full_pass);

    // rnea alone: inputs packed in Pinocchio's layout beforehand, one column per sample
    Eigen::MatrixXd Qp(model.nq, N), Vp(model.nv, N), Ap(model.nv, N), Tp(model.nv, N);
    for (long s = 0; s < N; ++s)
    {
      Qp.col(s) = pinocchio::neutral(model);
      for (int i = 0; i < n; ++i)
      {
        const Coord & c = coords[i];
        if (c.unbounded)
        {
          Qp(c.iq, s) = std::cos(Q[s * n + i]);
          Qp(c.iq + 1, s) = std::sin(Q[s * n + i]);
        }
        else
          Qp(c.iq, s) = Q[s * n + i];
        Vp(c.iv, s) = QD[s * n + i];
        Ap(c.iv, s) = QDD[s * n + i];
      }
    }
    std::vector<double> bare = time_passes([&]() {
      for (long s = 0; s < N; ++s)
        Tp.col(s) = pinocchio::rnea(model, data, Qp.col(s), Vp.col(s), Ap.col(s));
    });

    // the mass matrix: crba fills the upper triangle; what it gives is written, symmetric
    std::vector<double> Mout(N * n * n), QDDout(N * n);
    double crba_check = 0.0;
    std::vector<double> crba = time_passes([&]() {
      for (long s = 0; s < N; ++s)
        crba_check += pinocchio::crba(model, data, Qp.col(s))(0, model.nv - 1);
    });
    // the same with every sample's matrix written out, as ours is (into memory written before,
    // where ours gets a fresh array): what a user of crba needs for N states
    auto crba_stored_pass = [&]() {
      for (long s = 0; s < N; ++s)
      {
        pinocchio::crba(model, data, Qp.col(s));
        for (int i = 0; i < n; ++i)
          for (int k = 0; k < n; ++k)
          {
            const int a = std::min(coords[i].iv, coords[k].iv), b = std::max(coords[i].iv,
                                                                              coords[k].iv);
            Mout[(s * n + i) * n + k] = data.M(a, b);
          }
      }
    };
    crba_stored_pass();
    std::vector<double> crba_stored = time_passes(crba_stored_pass);
    // forward dynamics by articulated bodies, fed rnea's torques: gives the accelerations back
    double aba_check = 0.0;
    std::vector<double> aba = time_passes([&]() {
      for (long s = 0; s < N; ++s)
        aba_check += pinocchio::aba(model, data, Qp.col(s), Vp.col(s), Tp.col(s))[0];
    });
    for (long s = 0; s < N; ++s)
    {
      pinocchio::aba(model, data, Qp.col(s), Vp.col(s), Tp.col(s));
      for (int i = 0; i < n; ++i)
        QDDout[s * n + i] = data.ddq[coords[i].iv];
    }
    for (auto && [suffix, values] : {std::pair<const char *, std::vector<double> *>{".M", &Mout},
                                     {".qdd", &QDDout}})
    {
      const std::string path = std::string(argv[6]) + suffix;
      FILE * f = std::fopen(path.c_str(), "wb");
      if (!f || std::fwrite(values->data(), sizeof(double), values->size(), f) != values->size())
        throw std::runtime_error("cannot write " + path);
      std::fclose(f);
    }

    // the joint-torque regressor (nv x 10 njoints per sample): identification's baseline
    double reg_check = 0.0;
    std::vector<double> reg = time_passes([&]() {
      for (long s = 0; s < N; ++s)
        reg_check += pinocchio::computeJointTorqueRegressor(model, data, Qp.col(s), Vp.col(s),
                                                            Ap.col(s))(0, 0);
    });

    std::printf("nq %d\nnv %d\nn %d\nmax_abs_tau %.17g\n", model.nq, model.nv, n, max_abs);
    std::printf("regressor_best_ns %.6g\nregressor_median_ns %.6g\nregressor_check %.17g\n",
                *std::min_element(reg.begin(), reg.end()), median(reg), reg_check);
    std::printf("best_ns %.6g\nmedian_ns %.6g\n", *std::min_element(full.begin(), full.end()),
                median(full));
    std::printf("rnea_best_ns %.6g\nrnea_median_ns %.6g\n",
                *std::min_element(bare.begin(), bare.end()), median(bare));
    std::printf("crba_best_ns %.6g\ncrba_median_ns %.6g\ncrba_check %.17g\n",
                *std::min_element(crba.begin(), crba.end()), median(crba), crba_check);
    std::printf("crba_stored_best_ns %.6g\ncrba_stored_median_ns %.6g\n",
                *std::min_element(crba_stored.begin(), crba_stored.end()), median(crba_stored));
    std::printf("aba_best_ns %.6g\naba_median_ns %.6g\naba_check %.17g\n",
                *std::min_element(aba.begin(), aba.end()), median(aba), aba_check);
    std::printf("check %.17g\n", Tp.cwiseAbs().sum());
  }
  catch (const std::exception & e)
  {
    std::fprintf(stderr, "pinocchio_native: %s\n", e.what());
    return 1;
  }
  return 0;
}
