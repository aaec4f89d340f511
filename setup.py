"""Build hook: the wheel carries the SILO4 xacro inside the package.

``urdf/silo4.urdf.xacro`` at the repository top stays the one source of the robot; building a
wheel copies it to ``silo4kin/data/silo4.urdf.xacro``, where ``silo4kin.robot`` finds it with
importlib.resources once installed (a checkout or an editable install reads urdf/ directly).
MANIFEST.in puts urdf/ into the sdist, so a wheel built from the sdist has it too.
tests/test_packaging.py builds a wheel and fails if the file is missing from it.
"""

from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROBOT_SOURCE = Path("urdf") / "silo4.urdf.xacro"
ROBOT_IN_PACKAGE = Path("silo4kin") / "data" / "silo4.urdf.xacro"


class BuildPyWithRobot(build_py):
    """build_py, plus the SILO4 xacro copied into silo4kin/data/."""

    def run(self) -> None:
        super().run()
        if not self.editable_mode:
            target = Path(self.build_lib) / ROBOT_IN_PACKAGE
            self.mkpath(str(target.parent))
            self.copy_file(str(ROBOT_SOURCE), str(target))

    def get_outputs(self, include_bytecode: bool = True) -> list[str]:
        outputs = super().get_outputs(include_bytecode)
        if not self.editable_mode:
            outputs.append(str(Path(self.build_lib) / ROBOT_IN_PACKAGE))
        return outputs


setup(cmdclass={"build_py": BuildPyWithRobot})
