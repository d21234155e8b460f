from ._native import Image as Image
from ._native import PointCloud as PointCloud
from ._native import compare as compare
from ._native import read as read
from ._native import render as render
from ._native import tour as tour
