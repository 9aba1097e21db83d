"""The line that explains a printed NEES."""

PER_DOF = ("NEES per degree of freedom: 1 when the covariance is honest, above 1 overconfident "
           "(errors larger than it claims), below 1 conservative; see tools/eval/README.md, "
           "\"Reading the numbers\".")
POSITION = ("Position NEES (3 degrees of freedom): 3 on average when the covariance is honest, "
            "above overconfident (errors larger than it claims), below conservative; see "
            "tools/eval/README.md, \"Reading the numbers\".")
