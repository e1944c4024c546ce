// The experiment file and its CSV: what is read, and a located error for each mistake.
#include "fitting/experiment.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace tactus::fitting {
namespace {

namespace fs = std::filesystem;

class ExperimentFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tactus_fit_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    write("curve.csv", "# a loading curve\ndepth,force\n0.0001,0.01\n0.0002,0.03\n0.0003,0.05\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }

  static std::string experiment(const std::string& material = "model = \"corotational\"\npoisson_ratio = 0.45\n",
                                const std::string& data = "file = \"curve.csv\"\n",
                                const std::string& free = "young_modulus") {
    return "[indenter]\nshape = \"sphere\"\nradius = 0.005\n"
           "[specimen]\nsize = [0.04, 0.04]\nthickness = 0.01\ncells = [8, 8, 4]\n"
           "[material]\n" + material + "[fit]\nfree = [\"" + free + "\"]\n[data]\n" + data;
  }

  /// The error's text for `toml`, or "" when it reads.
  std::string error_of(const std::string& toml) const {
    try {
      (void)parse_experiment(toml, "exp.toml", dir_);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(ExperimentFile, ReadsTheIndenterSpecimenMaterialAndCurve) {
  const Experiment e = parse_experiment(experiment(), "exp.toml", dir_);
  EXPECT_EQ(e.indenter.shape, IndenterShape::sphere);
  EXPECT_DOUBLE_EQ(e.indenter.radius, 0.005);
  EXPECT_EQ(e.specimen.cells[2], 4);
  EXPECT_EQ(e.kind, CurveKind::depth_force);
  ASSERT_EQ(e.x.size(), 3U);
  EXPECT_DOUBLE_EQ(e.y[2], 0.05);
  ASSERT_NE(e.find("young_modulus"), nullptr);
  EXPECT_TRUE(e.find("young_modulus")->free);
  EXPECT_FALSE(e.find("young_modulus")->value.has_value());  // the analytic guess fills it
  EXPECT_DOUBLE_EQ(*e.find("poisson_ratio")->value, 0.45);
  EXPECT_FALSE(e.find("poisson_ratio")->free);
}

TEST_F(ExperimentFile, ASpringNetworkTakesItsYoungModulusAlone) {
  const Experiment e = parse_experiment(experiment("model = \"mass_spring\"\n"), "exp.toml", dir_);
  EXPECT_TRUE(e.mass_spring);
  EXPECT_EQ(e.model_name(), "mass_spring");
  ASSERT_EQ(e.parameters.size(), 1U);
  EXPECT_EQ(e.parameters[0].name, "young_modulus");
  const std::string error = error_of(experiment("model = \"mass_spring\"\npoisson_ratio = 0.45\n"));
  EXPECT_NE(error.find("material.poisson_ratio"), std::string::npos) << error;
  EXPECT_NE(error.find("a spring network's Poisson ratio is 1/4 at best"), std::string::npos) << error;
}

TEST_F(ExperimentFile, AFingerTakesItsElasticityAndAFingerpadItsLaw) {
  auto with = [](const std::string& indenter) {
    std::string text = experiment();
    const std::string sphere = "[indenter]\nshape = \"sphere\"\nradius = 0.005\n";
    return indenter + text.substr(sphere.size());
  };
  Experiment e = parse_experiment(with("[indenter]\nshape = \"finger\"\nradius = 0.008\nyoung_modulus = 2e5\n"),
                                  "exp.toml", dir_);
  EXPECT_EQ(e.indenter.shape, IndenterShape::finger);
  EXPECT_TRUE(e.indenter.round());
  EXPECT_DOUBLE_EQ(e.indenter.finger.youngs_modulus, 2e5);
  EXPECT_DOUBLE_EQ(e.indenter.finger.poisson_ratio, 0.48);  // the scenes' sphere tool's
  e = parse_experiment(with("[indenter]\nshape = \"fingerpad\"\nradius = 0.008\nm = 1500\n"), "exp.toml", dir_);
  EXPECT_EQ(e.indenter.shape, IndenterShape::fingerpad);
  EXPECT_DOUBLE_EQ(e.indenter.pad.b, 190.0);  // the scenes' fingerpad algorithm's
  EXPECT_DOUBLE_EQ(e.indenter.pad.m, 1500.0);

  std::string error = error_of(with("[indenter]\nshape = \"sphere\"\nradius = 0.008\nyoung_modulus = 2e5\n"));
  EXPECT_NE(error.find("indenter.young_modulus"), std::string::npos) << error;
  EXPECT_NE(error.find("a finger's"), std::string::npos) << error;
  error = error_of(with("[indenter]\nshape = \"finger\"\nradius = 0.008\nb = 100\n"));
  EXPECT_NE(error.find("indenter.b"), std::string::npos) << error;
  error = error_of(with("[indenter]\nshape = \"finger\"\nradius = 0.008\npoisson_ratio = 0.7\n"));
  EXPECT_NE(error.find("indenter.poisson_ratio"), std::string::npos) << error;
  write("relax.csv", "time,force\n0.1,0.05\n0.5,0.04\n1.0,0.035\n");
  const std::string relaxation = with("[indenter]\nshape = \"fingerpad\"\nradius = 0.008\n");
  error = error_of(relaxation.substr(0, relaxation.find("[material]")) +
                   "[material]\nmodel = \"linear\"\npoisson_ratio = 0.45\n[material.viscoelastic]\nmodel = "
                   "\"prony\"\nterms = [{ g = 0.3, tau = 1.0 }]\n[fit]\nfree = [\"young_modulus\"]\n[data]\n"
                   "file = \"relax.csv\"\ndepth = 0.001\nramp_time = 0.1\n");
  EXPECT_NE(error.find("a finger presses loading curves"), std::string::npos) << error;
}

TEST_F(ExperimentFile, MooneyRivlinAndPronyParameters) {
  write("relax.csv", "time,force\n0,0\n0.1,1\n0.5,0.8\n2,0.6\n");
  const Experiment e = parse_experiment(
      experiment("model = \"mooney_rivlin\"\nc10 = 1000\nc01 = 200\nkappa = 1e5\n"
                 "viscoelastic = { model = \"prony\", terms = [{ g = 0.3, tau = 0.5 }] }\n",
                 "file = \"relax.csv\"\ndepth = 0.001\nramp_time = 0.1\n", "c10"),
      "exp.toml", dir_);
  std::vector<std::string> names;
  for (const auto& p : e.parameters) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"c10", "c01", "kappa", "g1", "tau1"}));
  EXPECT_EQ(e.kind, CurveKind::time_force);
  EXPECT_DOUBLE_EQ(e.hold.value, 0.001);
  const physics::FemMaterial m = make_material(e, {1000, 200, 1e5, 0.3, 0.5});
  EXPECT_DOUBLE_EQ(*m.c10, 1000);
  EXPECT_NEAR(m.shear_modulus(), 2 * 1200, 1e-6);  // μ = 2 (C10 + C01) through E and ν
  ASSERT_EQ(m.prony.size(), 1U);
  EXPECT_DOUBLE_EQ(m.prony[0].tau, 0.5);
}

TEST_F(ExperimentFile, MisspeltKeyIsLocatedWithASuggestion) {
  const std::string err = error_of(experiment("model = \"corotational\"\npoison_ratio = 0.45\n"));
  EXPECT_NE(err.find("exp.toml:"), std::string::npos) << err;
  EXPECT_NE(err.find("did you mean 'poisson_ratio'"), std::string::npos) << err;
}

TEST_F(ExperimentFile, KeyOfAnotherLawIsRefused) {
  const std::string err = error_of(experiment("model = \"corotational\"\nc10 = 100\n"));
  EXPECT_NE(err.find("'c10' does not belong"), std::string::npos) << err;
}

TEST_F(ExperimentFile, WrongColumnIsNamedWithItsLine) {
  write("bad.csv", "depth,pressure\n0.1,1\n");
  const std::string err = error_of(experiment("model = \"linear\"\n", "file = \"bad.csv\"\n"));
  EXPECT_NE(err.find("bad.csv:1"), std::string::npos) << err;
  EXPECT_NE(err.find("depth,force"), std::string::npos) << err;
}

TEST_F(ExperimentFile, MissingColumnIsNamedWithItsLine) {
  write("bad.csv", "depth,force\n0.1,1\n0.2\n");
  const std::string err = error_of(experiment("model = \"linear\"\n", "file = \"bad.csv\"\n"));
  EXPECT_NE(err.find("bad.csv:3"), std::string::npos) << err;
  EXPECT_NE(err.find("two comma-separated columns"), std::string::npos) << err;
}

TEST_F(ExperimentFile, DepthThatDoesNotIncreaseIsNamedWithItsLine) {
  write("bad.csv", "depth,force\n0.1,1\n0.3,2\n0.2,3\n");
  const std::string err = error_of(experiment("model = \"linear\"\n", "file = \"bad.csv\"\n"));
  EXPECT_NE(err.find("bad.csv:4"), std::string::npos) << err;
  EXPECT_NE(err.find("does not increase"), std::string::npos) << err;
}

TEST_F(ExperimentFile, NanIsNamedWithItsLine) {
  write("bad.csv", "depth,force\n0.1,1\n0.2,nan\n0.3,3\n");
  const std::string err = error_of(experiment("model = \"linear\"\n", "file = \"bad.csv\"\n"));
  EXPECT_NE(err.find("bad.csv:3"), std::string::npos) << err;
  EXPECT_NE(err.find("NaN"), std::string::npos) << err;
}

TEST_F(ExperimentFile, UnreadableDataFileIsNamed) {
  const std::string err = error_of(experiment("model = \"linear\"\n", "file = \"absent.csv\"\n"));
  EXPECT_NE(err.find("absent.csv"), std::string::npos) << err;
}

TEST_F(ExperimentFile, RelaxationNeedsItsHoldAndPronyTerms) {
  write("relax.csv", "time,force\n0,0\n0.1,1\n0.5,0.8\n");
  EXPECT_NE(error_of(experiment("model = \"linear\"\n", "file = \"relax.csv\"\n")).find("missing"), std::string::npos);
  EXPECT_NE(error_of(experiment("model = \"linear\"\n", "file = \"relax.csv\"\ndepth = 0.001\nramp_time = 0.1\n"))
                .find("needs [material.viscoelastic]"),
            std::string::npos);
}

TEST_F(ExperimentFile, CreepHoldsAForce) {
  write("creep.csv", "time,depth\n0.1,0.0002\n0.5,0.0003\n2,0.0004\n");
  const std::string prony = "model = \"linear\"\npoisson_ratio = 0.45\n"
                            "viscoelastic = { model = \"prony\", terms = [{ g = 0.3, tau = 0.5 }] }\n";
  const Experiment e =
      parse_experiment(experiment(prony, "file = \"creep.csv\"\nforce = 0.05\nramp_time = 0.1\n"), "exp.toml", dir_);
  EXPECT_EQ(e.kind, CurveKind::time_depth);
  EXPECT_DOUBLE_EQ(e.hold.value, 0.05);
  EXPECT_DOUBLE_EQ(e.hold.ramp_time, 0.1);
  EXPECT_NE(error_of(experiment(prony, "file = \"creep.csv\"\nramp_time = 0.1\n")).find("held force"), std::string::npos);
  EXPECT_NE(error_of(experiment(prony, "file = \"creep.csv\"\nforce = 0.05\ndepth = 0.001\nramp_time = 0.1\n"))
                .find("holds a force"),
            std::string::npos);
  EXPECT_NE(error_of(experiment("model = \"linear\"\npoisson_ratio = 0.45\n",
                                "file = \"creep.csv\"\nforce = 0.05\nramp_time = 0.1\n"))
                .find("needs [material.viscoelastic]"),
            std::string::npos);
}

TEST_F(ExperimentFile, FreeParameterMustBelongToTheLaw) {
  std::string toml = experiment();
  toml.replace(toml.find("[\"young_modulus\"]"), 17, "[\"mu\"]");
  const std::string err = error_of(toml);
  EXPECT_NE(err.find("'mu' is not one of"), std::string::npos) << err;
}

}  // namespace
}  // namespace tactus::fitting
