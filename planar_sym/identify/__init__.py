"""Identification of a robot's inertial and friction parameters from measured torques.

The steps, each a function of its own module:

* ``regressor(robot, q, qd, qdd)``: ``tau = Y pi`` (``regressor.py``), ``pi`` the
  ``standard_parameters(robot)`` (``standard.py``);
* ``base_parameters(robot)``: the combinations the torques determine (``base.py``);
* ``excite(robot, period_s, harmonics)``: an exciting periodic motion (``excite.py``);
* ``experiment(robot, t, q, tau)`` / ``read_experiment(robot, csv)``: measurements, filtered and
  differentiated where needed (``data.py``, ``csv_data.py``);
* ``identify(robot, experiments)``: the base parameters with standard deviations
  (``estimate.py``);
* ``physical_parameters`` and ``identified_robot``: a physically consistent robot that
  reproduces them (``physical.py``), and ``identified_description``: that robot as a
  description file (``description_file.py``).

``planar-sym excite`` and ``planar-sym identify`` run them from the command line.
"""

from .base import BaseParameters, base_parameters
from .csv_data import read_experiment
from .data import Experiment, experiment
from .description_file import identified_description
from .estimate import Estimate, identify, predicted_torques
from .excite import Excitation, Limits, default_limits, excite
from .fourier import FourierMotion
from .physical import PhysicalFit, identified_robot, physical_parameters
from .regressor import Regressors, regressor
from .standard import StandardParameters, standard_parameters

__all__ = ["BaseParameters", "Estimate", "Excitation", "Experiment", "FourierMotion", "Limits",
           "PhysicalFit", "Regressors", "StandardParameters", "base_parameters",
           "default_limits", "excite", "experiment", "identified_description", "identified_robot",
           "identify",
           "physical_parameters", "predicted_torques", "read_experiment", "regressor",
           "standard_parameters"]
