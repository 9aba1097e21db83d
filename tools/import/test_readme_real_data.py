"""README.md's "Try it on real data" tells a newcomer where MRCLAM comes from and where the tools
and tests look for it: the dataset's download page, and the folder mrclam_data.py searches."""

import os

import mrclam_data

README = os.path.join(mrclam_data.REPO, "README.md")


def real_data_section():
    with open(README, encoding="utf-8") as f:
        text = f.read()
    start = text.index("## Try it on real data")
    return text[start:text.index("\n## ", start + 1)]


def test_the_readme_says_where_to_download_mrclam():
    section = real_data_section()
    assert "http://asrl.utias.utoronto.ca/datasets/mrclam/" in section
    assert "MRCLAM_Dataset6.zip" in section


def test_the_readme_names_the_folder_the_tools_search():
    assert f"`../{mrclam_data.DATASET6}`" in real_data_section()
